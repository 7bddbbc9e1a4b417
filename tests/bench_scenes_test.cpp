// The bench's parts on the CPU backend (with a stand-in for an unavailable second backend): the
// synthetic surface's exact topology, kernel and scene series with their interleaving, the JSON
// structure and the tables. No timing is asserted beyond "positive".
#include <gtest/gtest.h>

#include "cube_scene.hpp"
#include <unistd.h>

#include <fstream>
#include <set>
#include <sstream>

#include "harness/bench.hpp"

using namespace fracref;
namespace fs = std::filesystem;

namespace {

using test_scenes::cube_mesh;
const char* const kCube = test_scenes::kCubeObj;

struct TempDir {
  fs::path path;
  TempDir() {
    static int n = 0;
    path = fs::temp_directory_path() / ("fracref_bench_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
};

/// The Morton code the bench sorts by (21 bits per axis over [-1.5, 1.5]³, z highest).
std::uint64_t spread3(std::uint64_t v) {
  std::uint64_t r = 0;
  for (int b = 0; b < 21; ++b) r |= ((v >> b) & 1u) << (3 * b);
  return r;
}
std::uint64_t morton(glm::vec3 p) {
  const glm::uvec3 q = glm::uvec3(glm::clamp((p + 1.5f) / 3.0f, 0.0f, 1.0f) * float((1 << 21) - 1));
  return spread3(q.x) | spread3(q.y) << 1 | spread3(q.z) << 2;
}

std::vector<BenchBackend> cpu_and_missing(ComputeBackend& cpu) {
  return {{"cpu", &cpu, ""}, {"vulkan", nullptr, "no driver in this test"}};
}

}  // namespace

TEST(Bench, SyntheticSurfaceHasExactTopologyAndConsistentArrays) {
  const BenchSurface s = make_bench_surface(100);
  ASSERT_EQ(s.positions.size(), 100u);
  ASSERT_EQ(s.faces.size(), 2u * 9 * 9);
  ASSERT_EQ(s.vf_offsets.size(), 101u);
  EXPECT_EQ(s.vf_offsets.back(), 3 * s.faces.size());
  EXPECT_EQ(s.points.size(), s.faces.size());
  EXPECT_EQ(s.fan_offsets.size(), s.faces.size() + 1);
  EXPECT_EQ(s.fan_pairs.size(), 3 * s.faces.size());
  std::set<std::pair<int, int>> nodes;
  for (const glm::vec4& p : s.positions) nodes.insert({int(std::lround((p.x + 1) * 4.5)), int(std::lround((p.y + 1) * 4.5))});
  EXPECT_EQ(nodes.size(), 100u);  // a permutation of the 10 x 10 grid
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t = s.faces[f];
    ASSERT_LT(std::max({t.x, t.y, t.z}), 100u);
    const glm::vec3 n = glm::cross(glm::vec3(s.positions[t.y] - s.positions[t.x]), glm::vec3(s.positions[t.z] - s.positions[t.x]));
    EXPECT_GT(n.z, 0.0f) << "face " << f;  // consistently oriented
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = t[k];
      bool listed = false;
      for (std::uint32_t i = s.vf_offsets[v]; i < s.vf_offsets[v + 1]; ++i) listed |= s.vf_faces[i] == f;
      EXPECT_TRUE(listed) << "face " << f << " missing from vertex " << v;
    }
  }
  // Vertices and faces (by centroid) in Morton order: their codes never decrease.
  for (std::size_t i = 1; i < s.positions.size(); ++i)
    EXPECT_LE(morton(glm::vec3(s.positions[i - 1])), morton(glm::vec3(s.positions[i]))) << i;
  auto centroid = [&](const glm::uvec4& f) {
    return glm::vec3(s.positions[f.x] + s.positions[f.y] + s.positions[f.z]) / 3.0f;
  };
  for (std::size_t f = 1; f < s.faces.size(); ++f)
    EXPECT_LE(morton(centroid(s.faces[f - 1])), morton(centroid(s.faces[f]))) << f;
}

TEST(Bench, Median) {
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 2.0, 3.0}), 2.5);
  EXPECT_EQ(median({7.0}), 7.0);
}

TEST(Bench, KernelSeriesInterleavedWithAnUnavailableBackend) {
  auto cpu = make_cpu_backend(1);
  KernelBenchOptions o;
  o.repeat = 2;
  o.sizes = {100, 400};
  o.min_sample_seconds = 0.001;
  std::vector<std::string> order;
  o.progress = [&](const std::string& what, double) { order.push_back(what); };
  const auto backends = cpu_and_missing(*cpu);
  const std::vector<KernelBenchResult> r = bench_kernels(backends, o);
  const char* kernels[] = {"pyramid", "pyramid", "call_k1k2", "call_k1k2", "call_k3", "call_k3",
                           "k1k2",    "k1k2",    "k3",        "k3",        "k1k2",    "k1k2",    "k3", "k3"};
  const std::size_t sizes[] = {262144, 262144, 9, 9, 9, 9, 100, 100, 100, 100, 400, 400, 400, 400};
  ASSERT_EQ(r.size(), 14u);
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(r[i].kernel, kernels[i]) << i;
    EXPECT_EQ(r[i].size, sizes[i]) << i;
    EXPECT_EQ(r[i].backend, i % 2 ? "vulkan" : "cpu");
    if (i % 2) {
      EXPECT_EQ(r[i].error, "unavailable: no driver in this test");
      EXPECT_TRUE(r[i].ms.empty());
    } else {
      EXPECT_TRUE(r[i].error.empty()) << r[i].error;
      ASSERT_EQ(r[i].ms.size(), 2u);
      EXPECT_GT(r[i].ms[0], 0.0);
      EXPECT_GE(r[i].calls_per_sample, 1);
    }
  }
  // Interleaved: both repeats of a size before the next size, kernels alternating within a repeat.
  const std::vector<std::string> expect = {"pyramid 262144 cpu", "pyramid 262144 cpu", "call_k1k2 9 cpu", "call_k3 9 cpu",
                                           "call_k1k2 9 cpu",    "call_k3 9 cpu",      "k1k2 100 cpu",    "k3 100 cpu",
                                           "k1k2 100 cpu",       "k3 100 cpu",         "k1k2 400 cpu",    "k3 400 cpu",
                                           "k1k2 400 cpu",       "k3 400 cpu",         "kernels done"};
  EXPECT_EQ(order, expect);

  const nlohmann::ordered_json j = bench_json({}, r, backends, 2, Stage::refine, {"a note"});
  EXPECT_EQ(j["backends"]["cpu"]["name"], "cpu");
  EXPECT_EQ(j["backends"]["vulkan"]["unavailable"], "no driver in this test");
  ASSERT_EQ(j["kernels"].size(), 14u);
  EXPECT_EQ(j["kernels"][6]["kernel"], "k1k2");
  EXPECT_EQ(j["kernels"][6]["samples_ms"].size(), 2u);
  EXPECT_TRUE(j["kernels"][6]["median_ms"].is_number());
  EXPECT_TRUE(j["kernels"][7]["median_ms"].is_null());
  EXPECT_TRUE(j["kernels"][7]["to_cpu"].is_null());
  EXPECT_FALSE(j["kernels"][6].contains("to_cpu"));
  EXPECT_EQ(j["results"].size(), 0u);
  EXPECT_EQ(j["notes"][0], "a note");

  const std::string table = kernel_table(r, backends);
  EXPECT_NE(table.find("vulkan/cpu"), std::string::npos) << table;
  EXPECT_NE(table.find("64^3 grid"), std::string::npos) << table;
  EXPECT_NE(table.find("n/a"), std::string::npos) << table;
  const std::size_t first = table.find("unavailable: no driver");
  ASSERT_NE(first, std::string::npos) << table;
  EXPECT_EQ(table.find("unavailable: no driver", first + 1), std::string::npos) << "said once:\n" << table;
}

TEST(Bench, SceneSeriesFromTheJobsOwnReports) {
  TempDir t;
  t.write("cube.obj", kCube);
  t.write("cube.mesh", cube_mesh(2));
  const fs::path scene = t.write("cube.json", R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
     "field": {"type": "marble", "resolution": [8, 8, 8]}, "refine": {"max_iterations": 3, "max_triangles": 500},
     "output": {"preview": false}})");
  const fs::path bad = t.write("bad.json", R"({"exterior": "cube.obj"})");
  fs::create_directories(t.path / "scratch");
  auto cpu = make_cpu_backend(1);
  SceneBenchOptions o;
  o.repeat = 2;
  o.stop_after = Stage::refine;
  o.scratch = t.path / "scratch";
  std::vector<std::string> order;
  o.progress = [&](const std::string& what, double) { order.push_back(what); };
  const auto backends = cpu_and_missing(*cpu);
  const auto r = bench_scenes({{"cube", scene}, {"wall", bad, 204, 208000, 13.6}}, backends, o);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].scene, "cube");
  EXPECT_EQ(r[0].backend, "cpu");
  EXPECT_TRUE(r[0].error.empty()) << r[0].error;
  EXPECT_EQ(r[0].setup.size(), 2u);
  EXPECT_EQ(r[0].refine.size(), 2u);
  EXPECT_EQ(r[0].total.size(), 2u);
  EXPECT_TRUE(r[0].pieces.empty());  // stopped after refine
  EXPECT_EQ(r[0].coarse_triangles, 8u);
  EXPECT_TRUE(r[0].refined_triangles.has_value());
  EXPECT_TRUE(r[0].iterations.has_value());
  EXPECT_EQ(r[0].final_energy.size(), 2u);
  EXPECT_TRUE(r[0].animate.empty());
  EXPECT_EQ(r[1].error, "unavailable: no driver in this test");
  EXPECT_NE(r[2].error.find("bad.json"), std::string::npos) << r[2].error;  // the failure is kept, the rest ran
  EXPECT_TRUE(r[2].total.empty());
  EXPECT_EQ(order, (std::vector<std::string>{"cube-cpu-1", "wall-cpu-1", "cube-cpu-2", "scenes done"}));
  EXPECT_TRUE(fs::is_empty(t.path / "scratch"));

  const nlohmann::ordered_json j = bench_json(r, {}, backends, 2, Stage::refine, {});
  EXPECT_EQ(j["stop_after"], "refine");
  EXPECT_EQ(j["results"][0]["median_seconds"].size(), 4u);  // setup, refine, kernels, total
  EXPECT_EQ(r[0].kernels.size(), 2u);
  EXPECT_TRUE(j["results"][0]["median_seconds"]["kernels"].is_number());
  EXPECT_TRUE(j["results"][0]["samples_seconds"].contains("kernels"));
  EXPECT_EQ(j["results"][0]["samples_seconds"]["refine"].size(), 2u);
  EXPECT_TRUE(j["results"][0]["paper_seconds"].is_null());
  EXPECT_EQ(j["results"][2]["paper_seconds"], 13.6);
  EXPECT_EQ(j["results"][2]["paper_triangles"]["refined"], 208000);
  EXPECT_TRUE(j["results"][0]["paper_triangles"].is_null());
  EXPECT_EQ(j["results"][1]["to_cpu"].size(), 0u);

  const std::string table = scene_table(r, 2, Stage::refine);
  EXPECT_NE(table.find("8 -> "), std::string::npos) << table;
  EXPECT_NE(table.find("13.60"), std::string::npos) << table;
  EXPECT_NE(table.find("204 -> 208000"), std::string::npos) << table;
  EXPECT_NE(table.find("Stopped after refine."), std::string::npos) << table;
  EXPECT_NE(table.find("! wall on cpu: "), std::string::npos) << table;
}
