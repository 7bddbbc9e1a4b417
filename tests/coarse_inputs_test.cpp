// Every example file of scenes/INPUTS.md, read exactly as printed there.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "coarse/animation.hpp"
#include "coarse/coarse_model.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {

// The fenced blocks that follow a `<!-- file: NAME -->` line, by NAME.
std::map<std::string, std::string> example_files() {
  std::ifstream in(std::filesystem::path(FRACREF_SOURCE_DIR) / "scenes" / "INPUTS.md");
  std::map<std::string, std::string> files;
  std::string line, name;
  bool inside = false;
  while (std::getline(in, line)) {
    if (inside) {
      if (line == "```") inside = false, name.clear();
      else files[name] += line + "\n";
    } else if (line.rfind("<!-- file: ", 0) == 0) {
      name = line.substr(11, line.size() - 11 - 4);
    } else if (!name.empty() && line.rfind("```", 0) == 0) {
      inside = true;
    }
  }
  return files;
}

class CoarseInputsDoc : public ::testing::Test {
 protected:
  void SetUp() override {
    files_ = example_files();
    for (const auto& [name, text] : files_) dir_.file(name, text);
  }
  std::filesystem::path path(const std::string& name) const { return dir_.path() / name; }

  test::TempDir dir_;
  std::map<std::string, std::string> files_;
};

TEST_F(CoarseInputsDoc, AllExamplesAreThere) {
  for (const char* name : {"cube.mesh", "cube.node", "cube.ele", "cube_cracks.txt", "split.mesh", "two_cubes.obj",
                           "frames/frame_0000.txt", "frames/frame_0001.txt", "parents.txt", "transforms.txt"})
    EXPECT_EQ(files_.count(name), 1u) << name;
}

TEST_F(CoarseInputsDoc, CubeInBothTetFormats) {
  for (const char* name : {"cube.mesh", "cube.ele"}) {
    const CoarseModel m = load_tet_model(path(name), {});
    EXPECT_EQ(m.piece_count, 2) << name;
    EXPECT_EQ(m.surface.face_count(), 2u) << name;
    EXPECT_EQ(m.hull.size(), 12u) << name;
    EXPECT_EQ(m.inverted_fixed, 0u) << name;
    EXPECT_EQ(validate(m.surface), "") << name;
  }
  const CoarseModel cracked = load_tet_model(path("cube.mesh"), path("cube_cracks.txt"));
  EXPECT_EQ(cracked.piece_count, 3);
  EXPECT_EQ(cracked.surface.face_count(), 3u);
  EXPECT_EQ(cracked.virtual_faces_added, 0u);
  EXPECT_EQ(validate(cracked.surface), "");
}

TEST_F(CoarseInputsDoc, SplitPairWithBackwardRemeshing) {
  const CoarseModel m = load_tet_model(path("split.mesh"), {});
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(m.surface.face_count(), 1u);
  const CoarseAnimation a = load_frames(path("frames/frame_{:04}.txt"), 0, 2, 24.0, path("parents.txt"), m);
  EXPECT_EQ(a.file_vertex_counts, (std::vector<std::size_t>{5, 8}));
  EXPECT_EQ(a.frames[0][6], glm::dvec3(1, 0, 0));
  EXPECT_EQ(a.frames[1][6], glm::dvec3(1, 0, 0.5));
}

TEST_F(CoarseInputsDoc, TwoCubesWithRigidMotion) {
  const CoarseModel m = load_pieces(path("two_cubes.obj"));
  EXPECT_EQ(m.surface.face_count(), 2u);
  EXPECT_EQ(m.hull.size(), 20u);
  EXPECT_EQ(validate(m.surface), "");
  const CoarseAnimation a = load_rigid(path("transforms.txt"), 24.0, m);
  ASSERT_EQ(a.frames.size(), 2u);
  // Model vertices: the left cube's in the order its faces first use them (f 1 3 4 2 ...).
  ASSERT_EQ(m.vertices[3], glm::dvec3(1, 0, 0));
  EXPECT_EQ(a.frames[1][3], glm::dvec3(0, 1, 0));  // turned a quarter about z
  EXPECT_EQ(a.frames[1][8], m.vertices[8] + glm::dvec3(0, 0, 0.5));
}

}  // namespace
}  // namespace fracref
