// `fracref refine` as a user runs it: a small two-piece cube scene end to end on the CPU backend
// (with no Vulkan driver visible), bad scenes refused with the key named, and output folders
// that are either complete or untouched.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>

#include "cube_scene.hpp"

#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

#include "cli_mesh_support.hpp"
#include "cli_support.hpp"
#include "io/mesh_io.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
using cli_test::creases;
namespace fs = std::filesystem;

namespace {

using test_scenes::cube_mesh;
const char* const kCube = test_scenes::kCubeObj;

std::string scene(const std::string& extra) {
  return R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
             "field": {"type": "marble", "resolution": [16, 16, 16]},
             "refine": {"max_iterations": 4, "max_triangles": 2000})" + extra + "}";
}

// The shortest edge of the surface in `ply`, as a fraction of its bounding box's diagonal.
double shortest_edge(const fs::path& ply) {
  const fracref::MeshSoup m = fracref::read_ply(ply);
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  double shortest = 1e300;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) shortest = std::min(shortest, glm::distance(m.positions[t[k]], m.positions[t[(k + 1) % 3]]));
  return shortest / glm::distance(lo, hi);
}

// The hairpin tips of the surface in `ply`: vertices off the rim (no edge of one face) whose
// junction edges (of three faces or more) include two less than `degrees` apart.
std::size_t hairpin_tips(const fs::path& ply, double degrees) {
  const fracref::MeshSoup m = fracref::read_ply(ply);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> faces;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++faces[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::vector<std::vector<std::uint32_t>> junction(m.positions.size());
  std::vector<char> rim(m.positions.size(), 0);
  for (const auto& [e, n] : faces) {
    if (n == 1) rim[e.first] = rim[e.second] = 1;
    if (n >= 3) junction[e.first].push_back(e.second), junction[e.second].push_back(e.first);
  }
  std::size_t tips = 0;
  for (std::uint32_t v = 0; v < junction.size(); ++v) {
    bool tip = false;
    for (std::size_t i = 0; i < junction[v].size() && !rim[v]; ++i)
      for (std::size_t j = i + 1; j < junction[v].size(); ++j) {
        const glm::dvec3 a = glm::normalize(m.positions[junction[v][i]] - m.positions[v]);
        const glm::dvec3 b = glm::normalize(m.positions[junction[v][j]] - m.positions[v]);
        tip = tip || glm::dot(a, b) > std::cos(degrees * M_PI / 180.0);
      }
    tips += tip;
  }
  return tips;
}

}  // namespace

TEST(CliRefine, SmallSceneRunsOnTheCpuBackendWithoutVulkan) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  auto s = t.write("scene.json", scene(""));
  fs::path out = t.path / "out";
  auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu --stop-after refine",
               "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent");
  ASSERT_EQ(r.code, 0) << r.err;
  // Piped: no progress, nothing but the one closing line (no stray diagnostics).
  EXPECT_EQ(r.err.rfind("fracref: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.out, "");
  for (const char* f : {"report.json", "fracture_surface.ply", "coarse_surface.ply", "exterior.ply", "preview.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::string report = slurp(out / "report.json");
  EXPECT_NE(report.find("\"backend\": \"cpu\""), std::string::npos);
  EXPECT_NE(report.find("\"coarse_triangles\": 8"), std::string::npos) << report;
  EXPECT_NE(report.find("\"iterations\""), std::string::npos);
  // Nothing is left beside the output folder.
  for (auto& e : fs::directory_iterator(t.path)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

// --backend auto without a Vulkan driver falls back to the CPU backend and says why, after the
// run; a run that fails says one thing, its error.
TEST(CliRefine, BackendAutoSaysWhyOnlyWhenTheRunSucceeds) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  auto s = t.write("scene.json", scene(""));
  const std::string no_vulkan = "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent";
  auto ok = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --stop-after refine", no_vulkan);
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err.rfind("fracref: backend auto -> cpu (", 0), 0u) << ok.err;
  EXPECT_EQ(std::count(ok.err.begin(), ok.err.end(), '\n'), 2) << ok.err;
  t.write("cube.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 nan 0\nEnd\n");
  auto bad = run("refine " + s.string() + " -o " + (t.path / "bad").string(), no_vulkan);
  EXPECT_NE(bad.code, 0);
  EXPECT_EQ(bad.err.find("backend auto"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(fs::exists(t.path / "bad"));
}

TEST(CliRefine, SameSeedSameBytes) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  auto s = t.write("scene.json", scene(""));
  for (const char* o : {"a", "b"})
    ASSERT_EQ(run("refine " + s.string() + " -o " + (t.path / o).string() + " --backend cpu --stop-after refine -q").code, 0);
  EXPECT_EQ(slurp(t.path / "a" / "fracture_surface.ply"), slurp(t.path / "b" / "fracture_surface.ply"));
}

TEST(CliRefine, AnyThreadCountGivesTheSameBytes) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(3));
  auto s = t.write("scene.json", scene(""));
  for (const char* n : {"1", "4"})
    ASSERT_EQ(run("refine " + s.string() + " -o " + (t.path / n).string() + " --backend cpu -q --threads " + n).code, 0);
  std::size_t compared = 0;
  for (auto& e : fs::recursive_directory_iterator(t.path / "1")) {
    if (!e.is_regular_file() || e.path().filename() == "report.json") continue;
    const fs::path other = t.path / "4" / fs::relative(e.path(), t.path / "1");
    EXPECT_EQ(slurp(e.path()), slurp(other)) << other;
    ++compared;
  }
  EXPECT_GT(compared, 5u);
  for (const char* picture : {"preview_surface.png", "preview_section.png"})
    EXPECT_TRUE(fs::exists(t.path / "1" / picture)) << picture;  // compared above like every file
  EXPECT_NE(slurp(t.path / "4" / "report.json").find("\"threads\": 4"), std::string::npos);
  EXPECT_EQ(run("refine " + s.string() + " -o " + (t.path / "0").string() + " --threads 0").code, 2);
}

// refine.fold_solves: where the fold guard holds a face's corners, solving the step again with
// them fixed lets their neighbours move around them rather than past them, which folded the
// surface into creases near the rims and junctions (the scratch marks of the Jell-O's and the
// clay's previews). On the Jell-O, a second solve leaves fewer than half the creases, and E no
// higher.
TEST(CliRefine, FoldSolvesLeaveFewerCreases) {
  TempDir t;
  std::size_t bent[2];
  double ratio[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = t.path / std::to_string(k + 1);
    const auto r = run("demo jello -o " + out.string() + " --backend cpu -q --stop-after refine --set refine.fold_solves=" +
                       std::to_string(k + 1));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto report = nlohmann::json::parse(slurp(out / "report.json"));
    EXPECT_EQ(report["stop_reason"], "converged");
    ratio[k] = report["quality"]["energy_ratio"].get<double>();
    bent[k] = creases(out / "fracture_surface.ply");
  }
  EXPECT_GT(bent[0], 40u);
  EXPECT_LT(2 * bent[1], bent[0]);
  EXPECT_LE(ratio[1], ratio[0]);
}

// refine.hairpin_collapse: a junction curve that turns back on itself leaves a tongue whose tip
// the flow cannot draw back (any step that moves it folds its faces), and on the pieces it stands
// as a spike. Collapsing the tips into the curve leaves the Jell-O fewer, and E no higher than
// half a percent above (the two runs end on different meshes, 30K and 41K triangles: the finer
// one can sit a little lower).
TEST(CliRefine, HairpinCollapsesLeaveFewerHairpinTips) {
  TempDir t;
  std::size_t tips[2], collapses[2] = {0, 0};
  double ratio[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = t.path / std::to_string(k);
    const auto r = run("demo jello -o " + out.string() + " --backend cpu -q --stop-after refine --set refine.hairpin_collapse=" +
                       (k == 0 ? "0" : "45"));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto report = nlohmann::json::parse(slurp(out / "report.json"));
    EXPECT_EQ(report["stop_reason"], "converged");
    ratio[k] = report["quality"]["energy_ratio"].get<double>();
    for (const auto& it : report["iterations"]) collapses[k] += it["collapses"].get<std::size_t>();
    tips[k] = hairpin_tips(out / "fracture_surface.ply", 45.0);
  }
  EXPECT_EQ(collapses[0], 0u);
  EXPECT_GT(collapses[1], 5u);
  EXPECT_GE(tips[0], 6u);
  EXPECT_LT(3 * tips[1], 2 * tips[0]);
  EXPECT_LE(ratio[1], 1.005 * ratio[0]);
}

// The collar at the rim (refine/rim_collar.hpp) splits each inner edge that leaves a rim vertex
// along B. Where two rim vertices' grazing edges met at a vertex, each pass split the other's new
// edge a quarter of the way along, and the new vertices closed in on one point: on the clay, edges
// 2.5e-9 of the diagonal long before the flow, needles that the flow then folded. A split whose
// vertex would land that near a face's third corner is not made.
TEST(CliRefine, TheRimCollarMakesNoNeedles) {
  TempDir t;
  const fs::path out = t.path / "clay";
  const auto r = run("demo clay -o " + out.string() + " --backend cpu -q --stop-after refine --set refine.max_iterations=0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(shortest_edge(out / "fracture_surface.ply"), 1e-6);
}

TEST(CliRefine, RimMotionKeyLetsTheRimSlide) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(3));
  auto s = t.write("scene.json", scene(""));
  for (const char* m : {"false", "true"})
    ASSERT_EQ(run("refine " + s.string() + " -o " + (t.path / m).string() +
                  " --backend cpu -q --stop-after refine --set refine.rim_motion=" + m).code, 0);
  EXPECT_NE(slurp(t.path / "false" / "fracture_surface.ply"), slurp(t.path / "true" / "fracture_surface.ply"));
}

// refine.relax from the CLI: the sheets' vertices move along the sheets as well, the pieces stage
// still builds valid pieces from the surface, and E does not rise.
TEST(CliRefine, RelaxKeyRelaxesTheSheetsAndThePiecesStayValid) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(3));
  auto s = t.write("scene.json", scene(""));
  for (const char* r : {"0", "0.5"}) {
    const auto res = run("refine " + s.string() + " -o " + (t.path / r).string() +
                         " --backend cpu -q --stop-after pieces --set refine.relax=" + r);
    ASSERT_EQ(res.code, 0) << res.err;
    const auto report = nlohmann::json::parse(slurp(t.path / r / "report.json"));
    // The flow's E takes ψ at the corners; quality's samples each face finely, so it may differ
    // from the flow's by rounding-sized amounts.
    EXPECT_LE(report["quality"]["energy_ratio"].get<double>(), 1.0 + 1e-4);
  }
  EXPECT_NE(slurp(t.path / "0" / "fracture_surface.ply"), slurp(t.path / "0.5" / "fracture_surface.ply"));
}

TEST(CliRefine, RigidTransformsOnATetMeshWhosePiecesShareVertices) {
  // One vertex per point, as a mesher writes it; the two halves move apart by rigid transforms.
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  const std::string id = " 1 0 0 0  0 1 0 0  0 0 1 ";
  t.write("rigid.txt", "0 0" + id + "0\n0 1" + id + "0\n1 0" + id + "0\n1 1" + id + "0.5\n");
  auto s = t.write("scene.json", scene(R"(, "animation": {"kind": "rigid", "transforms": "rigid.txt"})"));
  const fs::path out = t.path / "out";
  auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu -q");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
}

TEST(CliRefine, BadSceneNamesTheKeyAndLeavesTheOutputAlone) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  fs::path out = t.path / "out";
  fs::create_directories(out);
  t.write("out/previous.txt", "a previous complete run");
  t.write("out/.fracref-output", "previous.txt\n");  // a folder fracref wrote
  struct Case {
    std::string extra, expect;
  } cases[] = {{R"(, "refine2": {})", "refine2"},
               {R"(, "weights": {"strength": -1})", "weights.strength"},
               {R"(, "pyramid": {"levels": "five"})", "pyramid.levels"}};
  for (const Case& c : cases) {
    auto s = t.write("bad.json", scene(c.extra));
    auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
  }
  t.write("broken.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 nan 0\nEnd\n");
  auto s = t.write("mesh.json", R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "broken.mesh"},
                                    "field": {"type": "marble", "resolution": [8, 8, 8]}})");
  auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("broken.mesh:5"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out / "previous.txt"), "a previous complete run");
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 2);  // previous.txt and the marker
  for (auto& e : fs::directory_iterator(t.path)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

TEST(CliRefine, DemoListAndUnknownScene) {
  auto r = run("demo --list");
  EXPECT_EQ(r.code, 0);
  for (const char* n : {"bunny", "branch", "wall", "clay", "jello"}) EXPECT_NE(r.out.find(n), std::string::npos);
  r = run("demo volcano -o /tmp/never");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("volcano"), std::string::npos);
}

// The wall's material acts on its refined cracks: they move into the weak brick-mortar
// interfaces (the area under the weak threshold rises by over a third). With a margin around the
// grid and five pyramid levels the interfaces were lost, and the rise was 18%, as in a field of
// constant strength the cracks took the same shape.
TEST(CliRefine, DemoWallCracksMoveIntoTheInterfaces) {
  // The coarse cracks run in the middle of the mortar joints, between the two weak interfaces;
  // the refined ones move into them (issue 28's line: 1.5 times, and half the area). Coarser
  // thresholds than the demo's (15K triangles instead of 203K) for the test's time; the demo
  // itself gives 0.006 -> 0.67.
  TempDir t;
  auto r = run("demo wall -o " + (t.path / "wall").string() +
               " --backend cpu --stop-after refine -q --set refine.tau=4e-6 --set refine.delta=0.004");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json weak = nlohmann::json::parse(slurp(t.path / "wall" / "report.json"))["quality"]["weak_fraction"];
  EXPECT_GT(weak["refined"].get<double>(), 1.5 * weak["coarse"].get<double>()) << weak.dump();
  EXPECT_GT(weak["refined"].get<double>(), 0.5) << weak.dump();
  // The interfaces lie within reach of the coarse cracks: from within the refined cracks' p95
  // displacement of them, most of the coarse cracks' area could reach weak material.
  EXPECT_GT(weak["reachable"]["fraction"].get<double>(), 0.5) << weak.dump();
  EXPECT_LE(weak["reachable"]["half_radius"].get<double>(), weak["reachable"]["radius"].get<double>()) << weak.dump();
}

TEST(CliRefine, DemoWallRefinesIntoAValidSurface) {
  // Ten pieces with junctions everywhere: the refiner validates S before it returns, so a broken
  // junction (for instance a flip folding a face past another piece's) fails this run.
  TempDir t;
  // At the defaults' thresholds (the demo's finer ones take ten times longer).
  auto r = run("demo wall -o " + (t.path / "wall").string() +
               " --backend cpu --stop-after refine -q --set refine.tau=0.002 --set refine.delta=0.004");
  ASSERT_EQ(r.code, 0) << r.err;
  std::string report = slurp(t.path / "wall" / "report.json");
  EXPECT_NE(report.find("\"refined_triangles\""), std::string::npos);
  EXPECT_TRUE(fs::exists(t.path / "wall" / "input" / "wall.json"));
}

namespace {

// Runs `demo NAME --seed SEED` through the pieces stage with `extra` options and expects the
// pieces to pass their checks.
void expect_demo_pieces_ok(const std::string& name, int seed, const std::string& extra) {
  TempDir t;
  const fs::path out = t.path / name;
  auto r = run("demo " + name + " -o " + out.string() + " --seed " + std::to_string(seed) +
               " --backend cpu --stop-after pieces -q " + extra);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(out / "report.json").find("\"pieces_ok\": true"), std::string::npos);
}

}  // namespace

TEST(CliRefine, DemoWallSeedFourBuildsValidPieces) {
  // Issue 33: this seed once ended in "side component 1 holds pieces 0 and 7" (an internal error).
  // Capped at the wall's triangle count of that time (the demo now converges near 200K, which
  // took three and a half minutes under ASan here).
  expect_demo_pieces_ok("wall", 4, "--set refine.max_triangles=60000");
}

TEST(CliRefine, DemoClaySeedSixBuildsValidPieces) {
  // Issue 28: with longest-edge paths this seed split an edge of faces that touch another sheet
  // (3e-8 apart, where sheets meet at a junction on B) in its third iteration, and the new
  // vertex's rounding made the sheets cross: "invalid pieces: ... intersecting faces". The demo's
  // coarse layout has changed since (laid out by the material): this seed still runs end to end
  // here, and RefineLoop.SplitsThatWouldCrossATouchingSheetAreFlagged keeps the crossing itself.
  expect_demo_pieces_ok("clay", 6, "--set refine.max_iterations=3");
}

TEST(CliRefine, DemoClayWithASlidingRimBuildsValidPieces) {
  // Issue 28: with refine.rim_motion the clay's rim folded back along a B edge by its 14th
  // iteration (a rim vertex's two rim edges snapped onto the edge, one past the other's end), and
  // the pieces stage stopped: "exterior edge ...: a rim segment runs along it across another rim
  // point". The vertices of such a segment now stay where they were.
  expect_demo_pieces_ok("clay", 1, "--set refine.rim_motion=true --set refine.max_iterations=14");
}

TEST(CliRefine, DemoBunnyWithASlidingRimBuildsValidPieces) {
  // Issue 28: with refine.rim_motion two of the bunny's rim edges crossed inside a triangle of B
  // by its 9th iteration, and the pieces stage stopped: "... two traced paths cross". The moved
  // ends of rim edges that would cross now stay where they were.
  expect_demo_pieces_ok("bunny", 1, "--set refine.rim_motion=true --set refine.max_iterations=9");
}

TEST(CliRefine, SetOverridesSceneKeysAndTheDemoInputRecordsThem) {
  TempDir t;
  const fs::path out = t.path / "branch";
  auto r = run("demo branch -o " + out.string() +
               " --backend cpu --stop-after refine -q --set refine.tau=0.004 --set refine.max_iterations=3");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_LE(report["iterations"].size(), 3u);
  const nlohmann::json input = nlohmann::json::parse(slurp(out / "input" / "branch.json"));
  EXPECT_EQ(input["refine"]["tau"], 0.004);
  EXPECT_EQ(input["refine"]["max_iterations"], 3);
  // The same overrides on `refine`, from the recorded input: the same surface.
  const fs::path again = t.path / "again";
  r = run("refine " + (out / "input" / "branch.json").string() + " -o " + again.string() +
          " --backend cpu --stop-after refine -q --set refine.max_iterations=3");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(again / "fracture_surface.ply"), slurp(out / "fracture_surface.ply"));
}

TEST(CliRefine, BadSetIsAnInputErrorAndWritesNothing) {
  TempDir t;
  const fs::path out = t.path / "branch";
  for (const auto& [set, says] : std::vector<std::pair<std::string, std::string>>{
           {"refine.taux=1", "demo branch: key 'refine.taux': unknown key (did you mean 'tau'?)"},
           {"refine.tau=-1", "key 'refine.tau': must be in (0, 1)"},
           {"tau", "--set 'tau': expected KEY=VALUE"},
           {"refine=3", "key 'refine': expected an object"}}) {
    auto r = run("demo branch -o " + out.string() + " --backend cpu -q --set " + set);
    EXPECT_EQ(r.code, 2) << set;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << set;
  }
}

// Paper 4.2: the stress term keeps the surface near the coarse one, the more so the heavier it is.
TEST(CliRefine, DistanceWeightKeepsTheSurfaceNearTheCoarseOne) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  std::vector<nlohmann::json> reports;
  for (const char* w : {"0.5", "16"}) {
    // Three levels: a 16^3 grid has no room for the default five (its coarsest would be 1 node).
    auto s = t.write(std::string("scene_") + w + ".json",
                     scene(std::string(R"(, "pyramid": {"levels": 3}, "weights": {"distance": )") + w + "}"));
    const fs::path out = t.path / (std::string("out_") + w);
    auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu --stop-after refine -q");
    ASSERT_EQ(r.code, 0) << r.err;
    reports.push_back(nlohmann::json::parse(slurp(out / "report.json")));
  }
  for (const auto& j : reports) {
    const auto& d = j.at("distance_to_coarse");
    std::cout << "distance_to_coarse " << d.dump() << "\n";
    EXPECT_GT(d.at("max").get<double>(), 0.0);
    EXPECT_LE(d.at("mean").get<double>(), d.at("max").get<double>());
    EXPECT_LE(d.at("max").get<double>(), d.at("allowed").get<double>());
  }
  // 32 times the weight: the allowed distance shrinks 32-fold and the surface stays closer.
  EXPECT_NEAR(reports[0]["distance_to_coarse"]["allowed"].get<double>(),
              32.0 * reports[1]["distance_to_coarse"]["allowed"].get<double>(), 1e-9);
  EXPECT_LT(reports[1]["distance_to_coarse"]["mean"].get<double>(), 0.5 * reports[0]["distance_to_coarse"]["mean"].get<double>());
}

// A fracture of one piece has no fracture surface: a clear input error naming the mesh, not a
// crash in the distance grid.
TEST(CliRefine, OnePieceIsAnInputErrorNotACrash) {
  TempDir t;
  t.write("cube.obj", kCube);
  std::string mesh = cube_mesh(2);
  for (std::size_t at = mesh.find(" 1\n", mesh.find("Tetrahedra")); at != std::string::npos; at = mesh.find(" 1\n", at))
    mesh.replace(at, 3, " 0\n");  // every tetrahedron in piece 0
  t.write("cube.mesh", mesh);
  const fs::path s = t.write("scene.json", scene(""));
  const fs::path out = t.path / "out";
  const auto r = run("refine " + s.string() + " -o " + out.string() + " --backend cpu -q");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cube.mesh: the fracture has 1 piece(s) and no fracture surface"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// -o never replaces what fracref did not write: a scene file, or a folder of the user's files.
TEST(CliRefine, OutputRefusesUserFilesAndFolders) {
  TempDir t;
  const fs::path proj = t.path / "proj";
  fs::create_directories(proj);
  std::ofstream(proj / "notes.txt") << "mine\n";
  auto r = run("demo branch -o " + proj.string() + " --backend cpu -q --stop-after preprocess");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("fracref did not write"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(proj / "notes.txt"), "mine\n");
  r = run("demo branch -o " + (proj / "notes.txt").string() + " --backend cpu -q --stop-after preprocess");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(slurp(proj / "notes.txt"), "mine\n");
  // Its own output folder is replaced, unless something else was put in it.
  const fs::path out = t.path / "out";
  ASSERT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  ASSERT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  std::ofstream(out / "mine.txt") << "mine\n";
  EXPECT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 2);
  EXPECT_EQ(slurp(out / "mine.txt"), "mine\n");
  // An output of a fracref from before the marker (report.json and fracref's names only) is replaced.
  const fs::path old = t.path / "old";
  fs::create_directories(old / "pieces");
  std::ofstream(old / "report.json") << "{}\n";
  EXPECT_EQ(run("demo branch -o " + old.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  EXPECT_TRUE(fs::exists(old / ".fracref-output"));
  fs::remove_all(old);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(t.path)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"out", "proj"}));  // no staging or input folders left
}

// A field that would not fit in memory is refused up front, naming the key and the estimate,
// before any file is read (it ended in a bare std::bad_alloc after minutes).
TEST(CliRefine, FieldTooLargeForTheMachineIsRefusedUpFront) {
  if (double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)) > 80e9) GTEST_SKIP() << "this machine has the memory";
  TempDir t;
  const fs::path s = t.write("big.json", R"({"exterior": "missing.obj", "fracture": {"kind": "tets", "mesh": "missing.mesh"},
                                           "field": {"type": "marble", "resolution": [1024, 1024, 1024]}})");
  const auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("big.json: key 'field.resolution': [1024, 1024, 1024] needs about 68.7 GB"), std::string::npos) << r.err;
}

// An input file larger than fracref reads whole is refused by its size, naming it, before a byte
// is read (a 30 GB OBJ ended in a bare std::bad_alloc). The file is sparse: no disk, no memory.
TEST(CliRefine, HugeInputFileIsRefusedBySize) {
  TempDir t;
  const fs::path huge = t.write("cube.obj", kCube);
  const std::uint64_t memory = std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGESIZE));
  fs::resize_file(huge, std::max<std::uint64_t>(memory, std::uint64_t(1) << 30));
  t.write("cube.mesh", cube_mesh(2));
  const auto s = t.write("scene.json", scene(""));
  const auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu -q");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("fracref: " + huge.string() + ": the file is ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(" fracref reads whole on this machine ("), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(t.path / "out"));
}

// Out of memory is one clear line and exit 1, never a bare "std::bad_alloc": the run is given
// less address space (ulimit -v) than its field needs.
TEST(CliRefine, OutOfMemoryIsOneClearMessage) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  const auto s = t.write("scene.json", R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
                                           "field": {"type": "marble", "resolution": [1024, 1024, 64]}})");
  const auto r = run("refine " + s.string() + " -o " + (t.path / "out").string() + " --backend cpu -q",
                     "ulimit -v 3000000; MALLOC_ARENA_MAX=2");
  if (r.err.find("AddressSanitizer") != std::string::npos) GTEST_SKIP() << "ASan cannot run under ulimit -v";
  if (r.code == 2 && r.err.find("needs about") != std::string::npos) GTEST_SKIP() << "the machine is too small: " << r.err;
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("fracref: out of memory", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.find("std::bad_alloc"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(t.path / "out"));
}
