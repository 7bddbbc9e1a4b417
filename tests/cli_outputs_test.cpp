// What an artist gets from a run: animation.glb valid for the Khronos glTF validator (0 errors,
// 0 warnings; skipped when node or the npm package gltf-validator is missing), rigid pieces moved
// by node transforms, frames/ off by default, and, when on, frames/ in either format that
// `fracref check` reads back against the glb (node transforms and morph weights applied).
#include <gtest/gtest.h>

#include <png.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "animate/gltf_writer.hpp"
#include "cli_support.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
namespace fs = std::filesystem;

namespace {

constexpr const char* kQuick = " --backend cpu -q --set refine.tau=0.002 --set refine.delta=0.004";

// Runs the validator script on `glb`; skips the calling test when it cannot run.
::testing::AssertionResult validates(const fs::path& glb, bool& skipped) {
  const fs::path log = glb.string() + ".validator.txt";
  const std::string cmd = "node " + std::string(FRACREF_SOURCE_DIR) + "/scenes/tools/validate_gltf.js " + glb.string() + " >" +
                          log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  skipped = code == 77 || code == 127;  // the package, or node itself, is missing
  if (code == 0 || skipped) return ::testing::AssertionSuccess() << slurp(log);
  return ::testing::AssertionFailure() << "exit " << code << ": " << slurp(log);
}

nlohmann::json report_of(const fs::path& out) { return nlohmann::json::parse(slurp(out / "report.json")); }

// The RGB8 pixels of a PNG file; empty when it cannot be read.
std::vector<std::uint8_t> png_pixels(const fs::path& file, int& width, int& height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, file.string().c_str())) return {};
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr)) return {};
  width = int(image.width), height = int(image.height);
  return rgb;
}

}  // namespace

TEST(CliOutputs, DefaultRunHasNoFramesAndAGlbTheValidatorAccepts) {
  TempDir t;
  const fs::path out = t.path / "branch";
  auto r = run("demo branch -o " + out.string() + kQuick);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_EQ(report_of(out)["frames_written"], 0);
  EXPECT_NE(slurp(out / "pieces" / "piece_000.obj").find("\nvn "), std::string::npos);
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("skipped  glb_frames"), std::string::npos) << r.out;
  bool skipped = false;
  EXPECT_TRUE(validates(out / "animation.glb", skipped));
  if (skipped) GTEST_SKIP() << "node or the npm package gltf-validator is missing (bash .ci/setup test installs it)";
}

TEST(CliOutputs, FramesAsObjOnRequestMatchTheGlb) {
  TempDir t;
  const fs::path out = t.path / "branch";
  auto r = run("demo branch -o " + out.string() + kQuick + " --set output.frames=true --set output.frames_format='\"obj\"'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "frames" / "frame_0000.obj"));
  EXPECT_FALSE(fs::exists(out / "frames" / "positions.bin"));
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("passed  glb_frames"), std::string::npos) << r.out;
}

// The deforming demos: their glb (morph targets) against frames/positions.bin, read back by check.
// A few flow iterations only: the animation and its glb follow whatever surface the flow left.
class CliDeformingDemo : public ::testing::TestWithParam<const char*> {};

TEST_P(CliDeformingDemo, GlbMatchesItsFramesAndValidates) {
  TempDir t;
  const fs::path out = t.path / GetParam();
  auto r = run(std::string("demo ") + GetParam() + " -o " + out.string() + " --backend cpu -q --set output.frames=true --set refine.max_iterations=4");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "frames" / "topology.obj"));
  EXPECT_TRUE(fs::exists(out / "frames" / "positions.bin"));
  EXPECT_LT(report_of(out)["glb"]["rigid_pieces"].get<int>(), report_of(out)["pieces"].get<int>());
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("passed  glb_frames"), std::string::npos) << r.out;
  bool skipped = false;
  EXPECT_TRUE(validates(out / "animation.glb", skipped));
  if (skipped) GTEST_SKIP() << "node or the npm package gltf-validator is missing (bash .ci/setup test installs it)";
}

// --preview-frames: the Jell-O breaking up, its fracture faces in the jelly's red (preview.png's
// colours), not in the pieces' palette (whose red is pale beside it).
TEST(CliOutputs, PreviewFramesShowTheFractureFacesInTheMaterialsColours) {
  TempDir t;
  const fs::path out = t.path / "jello";
  auto r = run("demo jello -o " + out.string() + " --backend cpu -q --set refine.max_iterations=4 --preview-frames 4");
  ASSERT_EQ(r.code, 0) << r.err;
  int width = 0, height = 0;
  const std::vector<std::uint8_t> rgb = png_pixels(out / "preview_frames.png", width, height);
  ASSERT_FALSE(rgb.empty());
  EXPECT_EQ(width, 4 * 320);
  EXPECT_EQ(height, 240);
  std::size_t jelly = 0;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) jelly += rgb[i] > 90 && 100 * rgb[i + 1] < 35 * rgb[i];
  EXPECT_GT(jelly, 500u);
}

// The demos' deforming pieces move every vertex; sparse targets are made here: two tetrahedra
// sharing a face, the second stretched along z so that its vertices at z = 0 stay.
TEST(CliOutputs, SparseMorphTargetsValidate) {
  fracref::PieceSet set;
  set.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  set.pieces.resize(2);
  set.pieces[0].triangles = {{1, 2, 3}, {0, 2, 1}, {0, 1, 3}, {0, 3, 2}};
  set.pieces[0].inside = {1, 0, 0, 0};
  set.pieces[1].triangles = {{1, 2, 4}, {1, 3, 2}, {2, 3, 4}, {3, 1, 4}};
  set.pieces[1].inside = {0, 1, 0, 0};
  fracref::AnimationResult r;
  r.layout.vertices = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  r.layout.offsets = {0, 4, 8};
  for (int t = 0; t < 4; ++t) {
    std::vector<glm::dvec3> x;
    for (std::uint32_t v : {0, 1, 2, 3}) x.push_back(set.positions[v]);
    for (std::uint32_t v : {1, 2, 3, 4}) x.push_back(set.positions[v] * glm::dvec3(1.0, 1.0, 1.0 + 0.2 * t));
    r.frames.push_back(x);
  }
  TempDir t;
  const fs::path glb = t.path / "sparse.glb";
  fracref::write_animation_glb(set, r, glb);
  EXPECT_NE(slurp(glb).find("\"sparse\""), std::string::npos);
  bool skipped = false;
  EXPECT_TRUE(validates(glb, skipped));
  if (skipped) GTEST_SKIP() << "node or the npm package gltf-validator is missing (bash .ci/setup test installs it)";
}

INSTANTIATE_TEST_SUITE_P(ClayAndJello, CliDeformingDemo, ::testing::Values("clay", "jello"));
