// `fracref refine` with `fracture.kind: "cuts"`: a cube with one cut drawn halfway across it is
// completed by virtual fracture and cut into two pieces end to end.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
namespace fs = std::filesystem;

namespace {

const fs::path kCutsData = fs::path(FRACREF_SOURCE_DIR) / "tests" / "data" / "cuts";

const char* kCube =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";

// Refines `scene` (CPU backend, no Vulkan) into t/out and expects two pieces that pass check.
void expect_two_checked_pieces(const TempDir& t, const fs::path& scene) {
  const std::string out = (t.path / "out").string();
  auto r = run("refine " + scene.string() + " -o " + out + " --backend cpu -q",
               "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
  ASSERT_EQ(r.code, 0) << r.err;
  auto report = nlohmann::json::parse(slurp(t.path / "out" / "report.json"));
  EXPECT_EQ(report["pieces"], 2);
  r = run("check " + out);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
}

}  // namespace

TEST(CliCuts, AHalfwayCutBecomesTwoPieces) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cut.obj", "v 0.53 -0.2 -0.2\nv 0.53 0.5 -0.2\nv 0.53 0.5 1.2\nv 0.53 -0.2 1.2\nf 1 2 3 4\n");
  auto s = t.write("scene.json", R"({"exterior": "cube.obj", "fracture": {"kind": "cuts", "mesh": "cut.obj"},
    "field": {"type": "marble", "resolution": [16, 16, 16]}, "refine": {"max_iterations": 3, "max_triangles": 4000}})");
  auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu --stop-after pieces -q",
               "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
  ASSERT_EQ(r.code, 0) << r.err;
  std::string text = slurp(t.path / "out" / "report.json");
  auto report = nlohmann::json::parse(text);
  EXPECT_EQ(report["coarse_triangles"], 554) << text;  // as in scenes/INPUTS.md, "Exterior plus cuts"
  EXPECT_EQ(report["pieces"], 2) << text;
  EXPECT_EQ(report["pieces_ok"], true) << text;
}

TEST(CliCuts, ACutSmallerThanTheFirstCellGetsAFinerLattice) {
  TempDir t;
  t.write("cube.obj", kCube);
  // A small disc-like cut near a corner: at 24 cells per diagonal it crosses no tet face; the
  // automatic lattice (no cells_per_diagonal) refines until it does (48), a fixed 48 does too.
  t.write("small.obj", "v 0.2 0.02 0.02\nv 0.2 0.02 0.06\nv 0.2 0.06 0.06\nv 0.2 0.06 0.02\nf 1 2 3 4\n");
  const std::string scene = R"({"exterior": "cube.obj", "fracture": {"kind": "cuts", "mesh": "small.obj"CELLS},
    "field": {"type": "marble", "resolution": [8, 8, 8]}, "refine": {"max_iterations": 2, "max_triangles": 20000}})";
  auto at = [&](const std::string& name, const std::string& cells) {
    return t.write(name, std::string(scene).replace(scene.find("CELLS"), 5, cells));
  };
  auto r = run("refine " + at("coarse.json", R"(, "cells_per_diagonal": 24)").string() + " -o " +
               (t.path / "coarse").string() + " --backend cpu --stop-after preprocess");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("small.obj: cut 1 of 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("at 24 cells per diagonal"), std::string::npos) << r.err;
  r = run("refine " + at("auto.json", "").string() + " -o " + (t.path / "auto").string() +
          " --backend cpu --stop-after preprocess -q");
  EXPECT_EQ(r.code, 0) << r.err;
  r = run("refine " + at("fine.json", R"(, "cells_per_diagonal": 48)").string() + " -o " + (t.path / "fine").string() +
          " --backend cpu --stop-after preprocess -q");
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(CliCuts, ACutOutsideIsRefusedNamingTheFile) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("far.obj", "v 2 0 0\nv 2 1 0\nv 2 1 1\nf 1 2 3\n");
  auto s = t.write("scene.json", R"({"exterior": "cube.obj", "fracture": {"kind": "cuts", "mesh": "far.obj"},
    "field": {"type": "marble", "resolution": [8, 8, 8]}})");
  auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("far.obj: cut 1 of 1"), std::string::npos) << r.err;
}

// An oblique disc inside the cube (it stops 0.2 short of the faces) goes end to end as two
// pieces that `fracref check` accepts; it used to stop with "the coarse fracture surface is
// invalid", exit 2, as if the input were bad.
TEST(CliCuts, AnObliqueDiscInsideTheCubeGoesEndToEnd) {
  TempDir t;
  t.write("cube.obj", kCube);
  std::string disc = "v 0.52 0.47 0.5\n";
  const glm::dvec3 c(0.52, 0.47, 0.5), n = glm::normalize(glm::dvec3(0.3, 0.5, 0.81));
  const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0))), v = glm::cross(n, u);
  for (int s = 0; s < 16; ++s) {
    const double a = 2.0 * M_PI * s / 16;
    const glm::dvec3 p = c + 0.25 * (std::cos(a) * u + std::sin(a) * v);
    disc += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  }
  for (int s = 0; s < 16; ++s) disc += "f 1 " + std::to_string(2 + s) + " " + std::to_string(2 + (s + 1) % 16) + "\n";
  t.write("disc.obj", disc);
  auto s = t.write("scene.json", R"({"exterior": "cube.obj", "fracture": {"kind": "cuts", "mesh": "disc.obj"},
    "field": {"type": "marble", "resolution": [16, 16, 16]}, "refine": {"max_iterations": 3, "max_triangles": 4000}})");
  expect_two_checked_pieces(t, s);
}

// A plane through a bumpy sphere (tests/data/cuts/bumpy_sphere.obj: an icosphere of 320 faces
// with radius 1 + 0.3 sin(4x + 1) sin(4y + 2) sin(4z + 0.5)) that meets B at grazing angles and
// over concave parts, where rim chords of the coarse S run outside B: their faces must be trimmed
// to B before they are split along their traces, or the traced rim and the trimmed rim cross
// (issue 30, "two traced paths cross").
TEST(CliCuts, APlaneGrazingABumpySphereIsCutAlongIt) {
  TempDir t;
  fs::copy_file(kCutsData / "bumpy_sphere.obj", t.path / "bumpy.obj");
  t.write("cut.obj",
          "v 1.89010598 0.584303097 -3.33085727\nv 1.89010598 -3.44828757 0.349501318\n"
          "v -1.90444723 -0.802176233 3.24886116\nv -1.90444723 3.23041443 -0.431497426\nf 1 2 3 4\n");
  auto s = t.write("scene.json", R"({"exterior": "bumpy.obj", "fracture": {"kind": "cuts", "mesh": "cut.obj"},
    "field": {"type": "marble", "resolution": [16, 16, 16]}, "refine": {"max_iterations": 3}})");
  expect_two_checked_pieces(t, s);
}

// The lattice's zig-zag on B is not the input's: a cuts scene smooths its rim by default
// (kLatticeRimSmoothing passes), and says so; the scene's own value, 0 included, wins.
TEST(CliCuts, TheLatticesRimIsSmoothedUnlessTheSceneSaysOtherwise) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cut.obj", "v 0.53 -0.2 -0.2\nv 0.47 1.2 -0.2\nv 0.53 1.2 1.2\nv 0.47 -0.2 1.2\nf 1 2 3 4\n");
  const auto refine = [&](const std::string& extra) {
    auto s = t.write("scene.json", R"({"exterior": "cube.obj", "fracture": {"kind": "cuts", "mesh": "cut.obj"},
      "field": {"type": "marble", "resolution": [16, 16, 16]}, "refine": {"max_iterations": 2)" + extra + "}}");
    fs::remove_all(t.path / "out");
    auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu --stop-after refine -q",
                 "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(slurp(t.path / "out" / "report.json"));
  };
  const auto by_default = refine(""), off = refine(R"(, "rim_smoothing": 0)");
  EXPECT_EQ(by_default["rim_smoothing"], 2);
  EXPECT_EQ(off["rim_smoothing"], 0);
  // The flow starts from another rim.
  EXPECT_NE(by_default["iterations"][0]["energy"], off["iterations"][0]["energy"]);
}

// Two random planar cuts through the bunny (tests/data/cuts/bunny_two_cuts_narrow.obj; the 1st of
// 24 such inputs) where two sheets meet the exterior so close together that the set-up's
// embedding of the rim leaves two rim edges crossing inside one exterior triangle. The pieces
// stage cannot cut B there; the refiner says so before the flow, naming the edges, the triangle
// and where, with no output (before: an internal error from the pieces stage, after the whole
// refinement). A known limitation (README); when it is lifted this input should go end to end.
TEST(CliCuts, RimEdgesThatCrossOnTheExteriorStopTheRunBeforeTheFlowNamingWhere) {
  TempDir t;
  const fs::path inputs = fs::path(FRACREF_SOURCE_DIR) / "tests" / "data" / "inputs";
  auto s = t.write("scene.json", R"({"exterior": ")" + (inputs / "bunny_exterior.obj").string() +
                                     R"(", "fracture": {"kind": "cuts", "mesh": ")" +
                                     (kCutsData / "bunny_two_cuts_narrow.obj").string() +
                                     R"("}, "field": {"type": "marble", "resolution": [32, 32, 32]}})");
  const fs::path out = t.path / "out";
  auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu -q",
               "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("rim cannot be laid on the exterior: its edges "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" cross inside exterior triangle "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::distance(fs::directory_iterator(t.path), fs::directory_iterator{}), 1) << "only scene.json";
}
