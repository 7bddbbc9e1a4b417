// The refined fracture surface stays free of self-intersections at a finer split threshold than
// the demos use (the wall at tau 0.001 had 11 intersecting face pairs, made by edge flips, before
// flips were checked against the faces around them).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "geom/intersect.hpp"
#include "io/mesh_io.hpp"

namespace fs = std::filesystem;
using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;

TEST(CliCleanSurface, FinerWallRefinesWithoutSelfIntersections) {
  TempDir t;
  const fs::path gen = t.path / "gen";
  ASSERT_EQ(run("demo wall -o " + gen.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  nlohmann::json scene = nlohmann::json::parse(slurp(gen / "input" / "wall.json"));
  scene["refine"]["tau"] = 1e-5;
  scene["refine"]["delta"] = 0.002;
  scene["refine"]["max_iterations"] = 20;
  const fs::path path = gen / "input" / "wall_fine.json";
  std::ofstream(path, std::ios::binary) << scene.dump(1);
  const fs::path out = t.path / "out";
  auto r = run("refine " + path.string() + " -o " + out.string() + " --backend cpu -q --stop-after refine");
  ASSERT_EQ(r.code, 0) << r.err;
  const fracref::MeshSoup s = fracref::read_mesh(out / "fracture_surface.ply");
  ASSERT_GT(s.triangles.size(), 2000u);  // refined well past the coarse 206
  const auto hits = fracref::find_self_intersections(s.positions, s.triangles, 10);
  EXPECT_TRUE(hits.empty()) << hits.size() << " intersecting pairs, e.g. faces " << hits[0].first << " and "
                            << hits[0].second;
}
