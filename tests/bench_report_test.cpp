// The bench's reports from hand-made data: what a run's report.json gives (record_run), the
// comparison of a backend with cpu (ratios of paired runs with start-up, triangle and energy
// differences), the JSON's fields and values, the scene table and the Markdown report. No timing
// is measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>

#include "harness/bench.hpp"
#include "util/parallel.hpp"

using namespace fracref;
using nlohmann::ordered_json;

namespace {

/// The wall on cpu and on vulkan (3 runs each), and the branch on cpu with vulkan unavailable.
std::vector<SceneBenchResult> hand_made_results() {
  SceneBenchResult cpu;
  cpu.scene = "wall", cpu.backend = "cpu", cpu.backend_name = "cpu";
  cpu.setup = {1.0, 1.0, 1.0}, cpu.refine = {3.0, 3.0, 3.0}, cpu.pieces = {0.5, 0.5, 0.5};
  cpu.animate = {0.25, 0.25, 0.25}, cpu.total = {4.75, 4.75, 4.75};
  cpu.final_energy = {2.0, 2.0, 2.0};
  cpu.coarse_triangles = 204, cpu.refined_triangles = 1000, cpu.iterations = 12;
  cpu.paper_coarse_triangles = 204, cpu.paper_refined_triangles = 208000, cpu.paper_seconds = 13.6;
  SceneBenchResult vk = cpu;
  vk.backend = "vulkan", vk.backend_name = "vulkan (llvmpipe)", vk.startup_seconds = 0.5;
  vk.setup = {1.5, 1.5, 1.5}, vk.refine = {3.0, 3.5, 2.5}, vk.total = {5.25, 5.75, 4.75};
  vk.final_energy = {2.01, 2.01, 2.01}, vk.refined_triangles = 1012;
  SceneBenchResult branch_cpu;
  branch_cpu.scene = "branch", branch_cpu.backend = "cpu", branch_cpu.backend_name = "cpu";
  branch_cpu.setup = {0.1}, branch_cpu.refine = {0.2}, branch_cpu.pieces = {0.3}, branch_cpu.total = {0.6};
  branch_cpu.final_energy = {0.0}, branch_cpu.coarse_triangles = 60, branch_cpu.refined_triangles = 181;
  SceneBenchResult branch_vk;
  branch_vk.scene = "branch", branch_vk.backend = "vulkan", branch_vk.backend_name = "vulkan";
  branch_vk.error = "unavailable: no driver";
  return {cpu, vk, branch_cpu, branch_vk};
}

}  // namespace

TEST(BenchReport, RecordRunReadsEveryStageTheFinalEnergyAndTheCounts) {
  SceneBenchResult r;
  record_run(ordered_json::parse(R"({"coarse_triangles": 8, "refined_triangles": 40, "initial_energy": 9.0,
      "iterations": [{"energy": 5.0, "triangles": 20}, {"energy": 3.5, "triangles": 40}],
      "seconds": {"setup": 0.1, "refine": 0.2, "pieces": 0.3, "animate": 0.4, "total": 1.0}})"),
             r);
  record_run(ordered_json::parse(R"({"coarse_triangles": 8, "refined_triangles": 8, "initial_energy": 9.0,
      "iterations": [], "seconds": {"setup": 0.5, "refine": 0.0, "total": 0.5}})"),
             r);
  EXPECT_EQ(r.setup, (std::vector<double>{0.1, 0.5}));
  EXPECT_EQ(r.refine, (std::vector<double>{0.2, 0.0}));
  EXPECT_EQ(r.pieces, (std::vector<double>{0.3}));
  EXPECT_EQ(r.animate, (std::vector<double>{0.4}));
  EXPECT_EQ(r.total, (std::vector<double>{1.0, 0.5}));
  EXPECT_EQ(r.final_energy, (std::vector<double>{3.5, 9.0}));  // no iteration: the initial energy
  EXPECT_EQ(r.coarse_triangles, 8u);
  EXPECT_EQ(r.refined_triangles, 8u);  // the last run's
  EXPECT_EQ(r.iterations, 0u);

  SceneBenchResult pre;  // stopped after preprocess: no refine, no energy
  record_run(ordered_json::parse(R"({"coarse_triangles": 8, "seconds": {"setup": 0.1, "total": 0.1}})"), pre);
  EXPECT_TRUE(pre.final_energy.empty());
  EXPECT_FALSE(pre.refined_triangles.has_value());
  EXPECT_FALSE(pre.iterations.has_value());
  EXPECT_TRUE(pre.refine.empty());
}

// The refinement's stop reason and quality, the last run's (absent before refine).
TEST(BenchReport, RecordRunReadsTheStopReasonAndTheQuality) {
  SceneBenchResult r;
  record_run(ordered_json::parse(R"({"refined_triangles": 40, "stop_reason": "converged",
      "quality": {"energy_ratio": 0.7, "weak_fraction": {"coarse": 0.2, "refined": 0.3, "threshold": 0.25,
                                                      "reachable": {"radius": 0.02, "fraction": 0.35}}}})"),
             r);
  EXPECT_EQ(r.stop_reason, std::optional<std::string>("converged"));
  EXPECT_EQ(r.energy_ratio, std::optional<double>(0.7));
  EXPECT_EQ(r.weak_coarse, std::optional<double>(0.2));
  EXPECT_EQ(r.weak_refined, std::optional<double>(0.3));
  EXPECT_EQ(r.weak_reachable, std::optional<double>(0.35));
  const std::string table = scene_table({r}, 1, Stage::animate);
  EXPECT_NE(table.find("0.200 -> 0.300 (reach 0.350)"), std::string::npos) << table;
  record_run(ordered_json::parse(R"({"coarse_triangles": 8})"), r);
  EXPECT_FALSE(r.stop_reason.has_value());
  EXPECT_FALSE(r.energy_ratio.has_value());
  EXPECT_FALSE(r.weak_refined.has_value());
  EXPECT_FALSE(r.weak_reachable.has_value());
}

TEST(BenchReport, CompareBackendsPairsRunsAndAddsStartUp) {
  const std::vector<SceneComparison> c = compare_backends(hand_made_results());
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].scene, "wall");
  EXPECT_EQ(c[0].backend, "vulkan");
  // (1.5 + {3, 3.5, 2.5} + 0.5) / (1 + 3 + 0) = {1.25, 1.375, 1.125}
  ASSERT_EQ(c[0].setup_refine_ratios.size(), 3u);
  EXPECT_DOUBLE_EQ(c[0].setup_refine_ratios[1], 1.375);
  EXPECT_DOUBLE_EQ(*c[0].setup_refine_ratio, 1.25);
  EXPECT_DOUBLE_EQ(*c[0].total_ratio, 5.25 / 4.75);
  EXPECT_EQ(c[0].triangles_cpu, 1000u);
  EXPECT_EQ(c[0].triangles_other, 1012u);
  EXPECT_EQ(c[0].triangle_difference, 12);
  EXPECT_DOUBLE_EQ(*c[0].triangle_relative_difference, 0.012);
  EXPECT_DOUBLE_EQ(*c[0].energy_cpu, 2.0);
  EXPECT_NEAR(*c[0].energy_relative_difference, 0.005, 1e-12);
  // The unavailable backend: every figure missing.
  EXPECT_EQ(c[1].scene, "branch");
  EXPECT_EQ(c[1].triangles_cpu, 181u);
  EXPECT_FALSE(c[1].triangles_other.has_value());
  EXPECT_FALSE(c[1].triangle_difference.has_value());
  EXPECT_FALSE(c[1].energy_relative_difference.has_value());
  EXPECT_TRUE(c[1].setup_refine_ratios.empty());
  EXPECT_FALSE(c[1].setup_refine_ratio.has_value());
  EXPECT_FALSE(c[1].total_ratio.has_value());
}

TEST(BenchReport, CompareBackendsRelativeDifferencesAgainstZero) {
  std::vector<SceneBenchResult> r = hand_made_results();
  r[0].final_energy = {0.0}, r[1].final_energy = {0.0};
  r[0].refined_triangles = 0, r[1].refined_triangles = 5;
  const SceneComparison c = compare_backends(r)[0];
  EXPECT_EQ(c.energy_relative_difference, 0.0);  // both 0
  EXPECT_EQ(c.triangle_difference, 5);
  EXPECT_FALSE(c.triangle_relative_difference.has_value());  // only cpu is 0
  // A backend alone (no cpu result) is compared with nothing.
  EXPECT_TRUE(compare_backends({r[1]}).empty());
}

TEST(BenchReport, JsonCarriesEveryStageTheEnergyAndTheComparisons) {
  auto cpu = make_cpu_backend(1);
  const std::vector<BenchBackend> backends = {{"cpu", cpu.get(), "", 0.001}, {"vulkan", nullptr, "no driver"}};
  const ordered_json j = bench_json(hand_made_results(), {}, backends, 3, Stage::animate, {});
  EXPECT_EQ(j["stop_after"], "animate");
  EXPECT_EQ(j["backends"]["cpu"]["startup_seconds"], 0.001);
  const ordered_json& vk = j["results"][1];
  EXPECT_EQ(vk["median_seconds"]["animate"], 0.25);
  EXPECT_EQ(vk["samples_seconds"]["refine"], (std::vector<double>{3.0, 3.5, 2.5}));
  EXPECT_EQ(vk["to_cpu"]["animate"], 1.0);
  EXPECT_EQ(vk["final_energy"], 2.01);
  EXPECT_EQ(vk["samples_final_energy"].size(), 3u);
  EXPECT_EQ(vk["coarse_triangles"], 204);
  EXPECT_EQ(vk["refined_triangles"], 1012);
  EXPECT_EQ(vk["paper_seconds"], 13.6);
  EXPECT_DOUBLE_EQ(vk["refine_to_paper"].get<double>(), 3.0 / 13.6);
  EXPECT_FALSE(j["results"][2]["median_seconds"].contains("animate"));  // the branch did not animate

  ASSERT_EQ(j["comparisons"].size(), 2u);
  const ordered_json& c = j["comparisons"][0];
  EXPECT_EQ(c["scene"], "wall");
  EXPECT_EQ(c["triangles_cpu"], 1000);
  EXPECT_EQ(c["triangles_vulkan"], 1012);
  EXPECT_EQ(c["triangle_difference"], 12);
  EXPECT_DOUBLE_EQ(c["triangle_relative_difference"].get<double>(), 0.012);
  EXPECT_EQ(c["energy_cpu"], 2.0);
  EXPECT_EQ(c["energy_vulkan"], 2.01);
  EXPECT_NEAR(c["energy_relative_difference"].get<double>(), 0.005, 1e-12);
  EXPECT_EQ(c["setup_refine_ratio"], 1.25);
  EXPECT_EQ(c["setup_refine_ratios"].size(), 3u);
  EXPECT_DOUBLE_EQ(c["total_ratio"].get<double>(), 5.25 / 4.75);
  const ordered_json& none = j["comparisons"][1];
  EXPECT_EQ(none["scene"], "branch");
  EXPECT_TRUE(none["triangles_vulkan"].is_null());
  EXPECT_TRUE(none["triangle_difference"].is_null());
  EXPECT_TRUE(none["energy_relative_difference"].is_null());
  EXPECT_TRUE(none["setup_refine_ratio"].is_null());
}

TEST(BenchReport, SceneTableShowsStagesAndTheComparison) {
  const std::string t = scene_table(hand_made_results(), 3, Stage::animate);
  for (const char* header : {"triangles", "final energy", "setup s", "refine s", "pieces s", "animate s", "total s",
                             "paper s", "refine/paper", "vs cpu", "setup+refine", "refined triangles"})
    EXPECT_NE(t.find(header), std::string::npos) << header << "\n" << t;
  EXPECT_NE(t.find("204 -> 1012"), std::string::npos) << t;
  EXPECT_NE(t.find("2.01 "), std::string::npos) << t;  // the vulkan wall's final energy
  EXPECT_NE(t.find("204 -> 208000"), std::string::npos) << t;
  EXPECT_NE(t.find("13.60"), std::string::npos) << t;
  EXPECT_NE(t.find("0.221x"), std::string::npos) << t;  // refine 3 / paper 13.6
  // The comparison row of the wall: setup+refine, total, triangles, energy.
  const std::size_t second = t.find("setup+refine");
  ASSERT_NE(second, std::string::npos) << t;
  const std::size_t row = t.find("\nwall ", second);
  ASSERT_NE(row, std::string::npos) << t;
  std::istringstream cells(t.substr(row + 1, t.find('\n', row + 1) - row - 1));
  const std::vector<std::string> got{std::istream_iterator<std::string>(cells), std::istream_iterator<std::string>()};
  EXPECT_EQ(got, (std::vector<std::string>{"wall", "vulkan", "1.25x", "1.11x", "+12", "(+1.20%)", "+0.50%"})) << t;
  EXPECT_NE(t.find("vulkan 0.500 s"), std::string::npos) << t;  // the start-up, in the footer
  EXPECT_NE(t.find("  ! branch on vulkan: unavailable: no driver"), std::string::npos) << t;
  EXPECT_EQ(t.find("Stopped after"), std::string::npos) << t;  // the whole pipeline ran
  EXPECT_EQ(t.find("not robust"), std::string::npos) << t;
  EXPECT_NE(scene_table(hand_made_results(), 3, Stage::pieces).find("Stopped after pieces."), std::string::npos);
}

TEST(BenchReport, SceneTableWithoutASecondBackendHasNoComparison) {
  const std::vector<SceneBenchResult> r = hand_made_results();
  const std::string t = scene_table({r[0], r[2]}, 3, Stage::animate);
  EXPECT_EQ(t.find("setup+refine"), std::string::npos) << t;
  EXPECT_NE(t.find("0.250"), std::string::npos) << t;  // the wall's animate median
  EXPECT_TRUE(scene_table({}, 3, Stage::animate).empty());
}

namespace {

/// A backend that only has a name: the Markdown report reads nothing else.
class NamedBackend : public ComputeBackend {
 public:
  explicit NamedBackend(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  std::vector<Grid3> build_pyramid(const Grid3&, const PyramidOptions&) override { throw std::logic_error("unused"); }
  void set_field(const FieldGrid4&) override { throw std::logic_error("unused"); }
  void vertex_velocities(const SurfaceView&, std::span<glm::vec4>, std::span<glm::vec4>) override {
    throw std::logic_error("unused");
  }
  void sample_tests(std::span<const glm::vec4>, std::span<const glm::vec4>, const SampleView&,
                    std::span<glm::vec4>) override {
    throw std::logic_error("unused");
  }

 private:
  std::string name_;
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// The Markdown table that follows the line `heading` in `text`: its lines starting with '|'.
std::vector<std::string> table_after(const std::string& text, const std::string& heading) {
  const std::vector<std::string> lines = lines_of(text);
  std::vector<std::string> table;
  auto it = std::find(lines.begin(), lines.end(), heading);
  if (it == lines.end()) return table;
  for (++it; it != lines.end() && (it->empty() || (*it)[0] == '|'); ++it) {
    if (it->empty() && !table.empty()) break;
    if (!it->empty()) table.push_back(*it);
  }
  return table;
}

std::size_t pipes(const std::string& line) { return std::size_t(std::count(line.begin(), line.end(), '|')); }

}  // namespace

TEST(BenchReport, BackendKindNamesTheDevice) {
  NamedBackend cpu("cpu"), lavapipe("vulkan (llvmpipe (LLVM 15.0.6, 256 bits))"), gpu("vulkan (NVIDIA H100 80GB HBM3)");
  EXPECT_EQ(backend_kind({"cpu", &cpu, "", 0.0, 2}), "CPU backend, 2 threads");
  EXPECT_EQ(backend_kind({"cpu", &cpu, "", 0.0, 1}), "CPU backend, 1 thread");
  EXPECT_EQ(backend_kind({"cpu:3", &cpu, "", 0.0, 3}), "CPU backend, 3 threads");
  const int all = default_threads();  // "cpu" without a count: the default
  EXPECT_EQ(backend_kind({"cpu", &cpu, "", 0.0, 0}), "CPU backend, " + std::to_string(all) + (all == 1 ? " thread" : " threads"));
  EXPECT_EQ(backend_kind({"vulkan", &lavapipe, "", 0.0, 0}), "lavapipe (llvmpipe (LLVM 15.0.6, 256 bits))");
  EXPECT_EQ(backend_kind({"vulkan", &gpu, "", 0.0, 0}), "GPU (NVIDIA H100 80GB HBM3)");
  EXPECT_EQ(backend_kind({"vulkan", nullptr, "no driver", 0.0, 0}), "vulkan (unavailable)");
}

// The section docs/PERFORMANCE.md keeps per machine: a heading, one table per backend with a
// header, an alignment row and one row per scene, every row as wide as its header; the
// comparison and the kernels; the notes. Hand-made results: nothing is timed.
TEST(BenchReport, MarkdownHasOneTablePerBackend) {
  NamedBackend cpu("cpu"), lavapipe("vulkan (llvmpipe (LLVM 15.0.6, 256 bits))");
  const std::vector<BenchBackend> backends = {{"cpu", &cpu, "", 0.0, 2}, {"vulkan", &lavapipe, "", 0.5, 0}};
  std::vector<KernelBenchResult> kernels = {{"k1k2", 10000, "cpu", {1.0, 2.0, 3.0}, 1, ""},
                                            {"k1k2", 10000, "vulkan", {1.0, 1.0, 1.0}, 1, ""}};
  const std::string md = bench_markdown(hand_made_results(), kernels, backends, 3, Stage::refine, {"a note"},
                                        {"fracref bench --repeat 3", 2});
  const std::vector<std::string> lines = lines_of(md);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "## CPU backend, 2 threads; lavapipe (llvmpipe (LLVM 15.0.6, 256 bits))") << md;
  EXPECT_NE(md.find("`fracref bench --repeat 3`"), std::string::npos) << md;
  EXPECT_NE(md.find("2 hardware threads"), std::string::npos) << md;
  EXPECT_NE(md.find("Medians of 3 runs"), std::string::npos) << md;
  EXPECT_NE(md.find("Stopped after refine."), std::string::npos) << md;

  const std::vector<std::string> on_cpu = table_after(md, "### CPU backend, 2 threads");
  ASSERT_EQ(on_cpu.size(), 4u) << md;  // header, alignment, wall, branch
  EXPECT_EQ(on_cpu[0].rfind("| scene | triangles | final energy | stop |", 0), 0u) << on_cpu[0];
  EXPECT_EQ(on_cpu[1].rfind("|---|---|---:|", 0), 0u) << on_cpu[1];
  EXPECT_EQ(on_cpu[2].rfind("| wall | 204 → 1000 |", 0), 0u) << on_cpu[2];
  EXPECT_EQ(on_cpu[3].rfind("| branch | 60 → 181 |", 0), 0u) << on_cpu[3];
  for (const std::string& row : on_cpu) EXPECT_EQ(pipes(row), pipes(on_cpu[0])) << row;
  EXPECT_EQ(pipes(on_cpu[0]), 16u);  // 15 columns: the text table's without the backend

  const std::vector<std::string> on_vulkan = table_after(md, "### lavapipe (llvmpipe (LLVM 15.0.6, 256 bits))");
  ASSERT_EQ(on_vulkan.size(), 4u) << md;
  EXPECT_EQ(on_vulkan[2].rfind("| wall | 204 → 1012 |", 0), 0u) << on_vulkan[2];
  EXPECT_EQ(on_vulkan[3].rfind("| branch | - |", 0), 0u) << on_vulkan[3];  // unavailable there

  const std::vector<std::string> compared = table_after(md, "### Against the CPU backend");
  ASSERT_EQ(compared.size(), 4u) << md;  // header, alignment, wall, branch
  EXPECT_EQ(compared[2], "| wall | vulkan | 1.25x | 1.11x | +12 (+1.20%) | +0.50% |") << md;
  EXPECT_EQ(compared[3], "| branch | vulkan | - | - | - | - |") << md;  // no vulkan figures

  const std::vector<std::string> k = table_after(md, "### Kernels");
  ASSERT_EQ(k.size(), 3u) << md;
  EXPECT_EQ(k[0], "| kernel | size | cpu ms | vulkan ms | vulkan/cpu |");
  EXPECT_EQ(k[2], "| k1k2 | 10000 | 2.00 | 1.00 | 0.500x |");

  EXPECT_NE(md.find("\n- failed: branch on vulkan: unavailable: no driver\n"), std::string::npos) << md;
  EXPECT_NE(md.find("\n- a note\n"), std::string::npos) << md;
}

TEST(BenchReport, MarkdownSaysWhyABackendIsMissingAndEscapesCells) {
  NamedBackend cpu("cpu");
  std::vector<SceneBenchResult> results = {hand_made_results()[0]};
  results[0].scene = "a|b";
  const std::vector<BenchBackend> backends = {{"cpu", &cpu, "", 0.0, 2}, {"vulkan", nullptr, "no driver", 0.0, 0}};
  const std::string md = bench_markdown(results, {}, backends, 1, Stage::animate, {}, {});
  EXPECT_NE(md.find("### vulkan (unavailable)\n\nUnavailable: no driver\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| a\\|b | 204 → 1000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("Medians of 1 run,"), std::string::npos) << md;
  EXPECT_EQ(md.find("Stopped after"), std::string::npos) << md;
  EXPECT_EQ(md.find("### Kernels"), std::string::npos) << md;
  EXPECT_EQ(md.find("### Against"), std::string::npos) << md;
}
