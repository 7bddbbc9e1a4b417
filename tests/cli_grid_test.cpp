// `fracref refine` with a user strength grid (`field.type: "grid"`): the grid file's values are
// the strength ζ the report measures, and a grid that does not cover the exterior, a malformed
// grid or a resolution that disagrees with the file are refused naming the grid file.
#include <gtest/gtest.h>

#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "cube_scene.hpp"
#include "field/grid_file.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
namespace fs = std::filesystem;

namespace {

// The shared test cube (tests/cube_scene.hpp): a unit cube of n^3 cells, 6 tets each, labelled 0 below
// z = 0.5 and 1 above (MEDIT), and its exterior.
using test_scenes::cube_mesh;
const char* const kCube = test_scenes::kCubeObj;

std::string scene(const std::string& field) {
  return R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
             "field": )" + field + R"(, "refine": {"max_iterations": 3, "max_triangles": 2000}})";
}

// A grid of `n`^3 nodes over [lo, lo + span]^3 whose value is `value` + `slope`·x.
fracref::Grid3 grid(unsigned n, double lo, double span, float value, float slope = 0.0f) {
  fracref::Grid3 g;
  g.dims = glm::uvec3(n);
  g.origin = glm::dvec3(lo);
  g.cell = span / (n - 1);
  for (unsigned z = 0; z < n; ++z)
    for (unsigned y = 0; y < n; ++y)
      for (unsigned x = 0; x < n; ++x) g.values.push_back(value + slope * float(g.node_position(x, y, z).x));
  return g;
}

struct GridScene {
  TempDir t;
  GridScene() {
    t.write("cube.obj", kCube);
    t.write("cube.mesh", cube_mesh(2));
  }
  cli_test::Result refine(const std::string& field, const std::string& out = "out") {
    auto s = t.write("scene.json", scene(field));
    return run("refine " + s.string() + " -o " + (t.path / out).string() + " --backend cpu --stop-after refine -q",
               "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
  }
};

}  // namespace

TEST(CliGrid, BinaryGridIsTheStrengthTheReportMeasures) {
  GridScene s;
  fracref::write_strength_grid(s.t.path / "strength.grid", grid(12, -0.1, 1.2, 0.25f), true);
  auto r = s.refine(R"({"type": "grid", "file": "strength.grid"})");
  ASSERT_EQ(r.code, 0) << r.err;
  auto report = nlohmann::json::parse(slurp(s.t.path / "out" / "report.json"));
  EXPECT_EQ(report["coarse_triangles"], 8) << report.dump(2);
  EXPECT_NEAR(report["mean_strength"]["coarse"].get<double>(), 0.25, 1e-6) << report.dump(2);
  EXPECT_NEAR(report["mean_strength"]["refined"].get<double>(), 0.25, 1e-6) << report.dump(2);
  EXPECT_TRUE(fs::exists(s.t.path / "out" / "fracture_surface.ply"));
  // The kernels' share: one pyramid, one sample test per iteration, at least one K1+K2 each.
  const std::size_t iterations = report["iterations"].size();
  EXPECT_EQ(report["kernel_calls"]["pyramid"], 1) << report.dump(2);
  EXPECT_EQ(report["kernel_calls"]["k3"], iterations) << report.dump(2);
  EXPECT_GE(report["kernel_calls"]["k1k2"].get<std::size_t>(), iterations) << report.dump(2);
  const double kernels = report["seconds"]["kernels"].get<double>();
  EXPECT_GE(kernels, 0.0);
  EXPECT_NEAR(kernels, report["kernel_seconds"]["pyramid"].get<double>() + report["kernel_seconds"]["k1k2"].get<double>() +
                           report["kernel_seconds"]["k3"].get<double>(), 1e-12);
}

TEST(CliGrid, TextGridWithAMatchingResolutionRuns) {
  GridScene s;
  // ζ = 0.5 + 0.25 x: the coarse cut at z = 0.5 spans x in [0, 1], so its mean strength is 0.625.
  fracref::write_strength_grid(s.t.path / "s.grid", grid(9, 0.0, 1.0, 0.5f, 0.25f), false);
  auto r = s.refine(R"({"type": "grid", "file": "s.grid", "resolution": [9, 9, 9]})");
  ASSERT_EQ(r.code, 0) << r.err;
  auto report = nlohmann::json::parse(slurp(s.t.path / "out" / "report.json"));
  EXPECT_NEAR(report["mean_strength"]["coarse"].get<double>(), 0.625, 0.03) << report.dump(2);
}

TEST(CliGrid, BadGridsAreRefusedNamingTheFile) {
  GridScene s;
  fracref::write_strength_grid(s.t.path / "small.grid", grid(5, 0.0, 0.5, 1.0f), true);
  auto r = s.refine(R"({"type": "grid", "file": "small.grid"})");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("small.grid: the grid covers [0, 0, 0] .. [0.5, 0.5, 0.5] but the exterior's bounding box is "
                       "[0, 0, 0] .. [1, 1, 1]"),
            std::string::npos)
      << r.err;
  fracref::write_strength_grid(s.t.path / "ok.grid", grid(6, 0.0, 1.0, 1.0f), true);
  r = s.refine(R"({"type": "grid", "file": "ok.grid", "resolution": [8, 8, 8]})");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("ok.grid: dims 6 6 6 differ from the scene's field.resolution 8 8 8"), std::string::npos) << r.err;
  s.t.write("bad.grid", "fracref-grid 1\ndims 2 2 2\norigin 0 0 0\ncell 1\nformat text\nend_header\n1 2 3\n");
  r = s.refine(R"({"type": "grid", "file": "bad.grid"})");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.grid:7: too few values: 3 of the 8"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "out"));
}
