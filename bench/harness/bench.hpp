#pragma once
// `fracref bench`: the paper's scenes end to end and the three kernels on synthetic surfaces,
// on each compute backend, repeated and interleaved (the machine's speed drifts, so backends are
// compared as ratios of medians taken in one run), as tables and JSON.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "flow/backend.hpp"
#include "pipeline/job.hpp"

namespace fracref {

/// A backend to measure: `backend` null when it is unavailable, and `unavailable` says why.
struct BenchBackend {
  std::string key;                  ///< "cpu", "vulkan"
  ComputeBackend* backend = nullptr;
  std::string unavailable;
  /// Seconds its creation took (instance, device, pipelines; measured by the caller, 0 when not).
  /// A job creates its backend once, outside report.json's seconds, and the bench shares one
  /// backend between its runs: the Vulkan/CPU ratio adds this to every run.
  double startup_seconds = 0.0;
  /// Worker threads of its runs (the CPU kernels and every other stage); 0 = default_threads().
  int threads = 0;
};

/// Reports progress: what runs now and the fraction of all runs done.
using BenchProgress = std::function<void(const std::string& what, double fraction)>;

// ---------------------------------------------------------------------------------------------
// Scenes

struct BenchScene {
  std::string name;                 ///< "wall"
  std::filesystem::path scene_file;
  std::uint64_t paper_coarse_triangles = 0;   ///< the paper's figures (demo_scene_targets()); 0 = unknown
  std::uint64_t paper_refined_triangles = 0;
  double paper_seconds = 0.0;
};

/// The measurements of one (scene, backend) pair: one entry per run in every series (a series
/// whose stage did not run, e.g. animate on a scene without animation, stays empty).
struct SceneBenchResult {
  std::string scene, backend;       ///< backend key
  std::string backend_name;         ///< ComputeBackend::name()
  std::string error;                ///< why the runs stopped (unavailable backend or a failure)
  std::vector<double> setup, refine, pieces, animate, total;  ///< seconds from each run's report
  std::vector<double> kernels;  ///< seconds.kernels: time in the three kernels (pyramid, K1+K2, K3)
  std::vector<double> final_energy;  ///< each run's energy after its last refine iteration
  std::optional<std::uint64_t> coarse_triangles, refined_triangles;  ///< the last run's
  std::optional<std::uint64_t> iterations;
  std::optional<std::string> stop_reason;  ///< the last run's report.json stop_reason
  /// The last run's quality: energy_ratio and weak_fraction's coarse and refined.
  std::optional<double> energy_ratio, weak_coarse, weak_refined;
  std::optional<double> weak_reachable;  ///< quality.weak_fraction.reachable.fraction: the most within the p95 displacement
  std::uint64_t paper_coarse_triangles = 0, paper_refined_triangles = 0;  ///< from BenchScene
  double paper_seconds = 0.0;                                             ///< from BenchScene; 0 = unknown
  double startup_seconds = 0.0;     ///< from BenchBackend
};

struct SceneBenchOptions {
  int repeat = 3;
  Stage stop_after = Stage::animate;  ///< the whole pipeline
  std::filesystem::path scratch;    ///< an existing folder for the runs' outputs (each removed after)
  BenchProgress progress;
};

/// Appends one run's figures from its report.json to `r`: seconds.setup, .refine, .kernels,
/// .pieces, .animate and .total each to its series when present; the final energy (the last entry of
/// `iterations`, or `initial_energy` when no iteration ran) when the job refined; and the counts
/// coarse_triangles, refined_triangles and the number of iterations, the stop_reason and the
/// quality's energy_ratio and weak_fraction (replacing the last run's).
void record_run(const nlohmann::ordered_json& report, SceneBenchResult& r);

/// Runs every (scene, backend) pair options.repeat times, interleaved: for each repeat, for each
/// scene, for each backend. Each run goes through run_job into its own folder under
/// options.scratch, removed afterwards; the seconds are the job's own (report.json). A pair
/// whose run throws records the message and runs no more. Results in scene-major order.
std::vector<SceneBenchResult> bench_scenes(const std::vector<BenchScene>& scenes,
                                           const std::vector<BenchBackend>& backends,
                                           const SceneBenchOptions& options);

/// One scene on a backend against the same scene on "cpu", from the runs' medians.
struct SceneComparison {
  std::string scene, backend;       ///< backend: the key compared with "cpu" ("vulkan")
  std::optional<std::uint64_t> triangles_cpu, triangles_other;  ///< refined triangles
  std::optional<std::int64_t> triangle_difference;              ///< other - cpu
  std::optional<double> triangle_relative_difference;           ///< difference / cpu
  std::optional<double> energy_cpu, energy_other;               ///< median final energies
  std::optional<double> energy_relative_difference;             ///< (other - cpu) / |cpu|
  /// Per pair of runs i (the i-th run of each; runs are interleaved, so a pair ran side by
  /// side): (setup + refine + start-up) on the backend / the same on cpu. Empty without refine.
  std::vector<double> setup_refine_ratios;
  std::optional<double> setup_refine_ratio;  ///< the median of setup_refine_ratios
  std::optional<double> total_ratio;         ///< median total / cpu median total
};

/// One comparison per result whose backend is not "cpu" and whose scene has a "cpu" result, in
/// the results' order. A figure is nullopt when either side lacks it (an unavailable backend,
/// a failure, a stage that did not run); a relative difference also when the cpu figure is 0
/// and the other is not (0 when both are).
std::vector<SceneComparison> compare_backends(const std::vector<SceneBenchResult>& results);

// ---------------------------------------------------------------------------------------------
// Kernels

/// A synthetic fracture-surface-like mesh: a side×side grid on z = 0.2 sin(3x) cos(2y) over
/// [-1, 1]², side = round(sqrt(vertices)), vertices and faces in Morton order, with the
/// vertex→faces CSR and one K3 sample per face (at its centroid, its three edges as fan).
struct BenchSurface {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
  std::vector<std::uint32_t> vf_offsets, vf_faces;
  std::vector<glm::vec4> points;
  std::vector<std::uint32_t> fan_offsets;
  std::vector<glm::uvec2> fan_pairs;
  SurfaceView view() const { return {positions, faces, vf_offsets, vf_faces}; }
  SampleView samples() const { return {points, fan_offsets, fan_pairs}; }
};

/// \pre vertices >= 4.
BenchSurface make_bench_surface(std::size_t vertices);

/// The kernels' field: random values in [-1, 1] on a 64³ grid over [-1.1, 1.1]³, the same every
/// call (seeded).
FieldGrid4 make_bench_field();

/// One kernel at one size on one backend: milliseconds per call, one value per repeat.
struct KernelBenchResult {
  std::string kernel;   ///< "pyramid", "k1k2", "k3", "call_k1k2", "call_k3"
  std::size_t size = 0; ///< vertices (k1k2, k3, call_*), grid nodes (pyramid)
  std::string backend;  ///< backend key
  std::vector<double> ms;
  int calls_per_sample = 1;
  std::string error;
};

struct KernelBenchOptions {
  int repeat = 3;
  std::vector<std::size_t> sizes = {10'000, 100'000, 1'000'000};
  double min_sample_seconds = 0.02;  ///< fast calls are repeated until a sample takes this long
  BenchProgress progress;
};

/// Times, per backend, through the ComputeBackend interface: "pyramid" (build_pyramid of a
/// random 64³ grid, 5 levels), per size "k1k2" (vertex_velocities) and "k3" (sample_tests, one
/// sample per face), and the fixed cost of a call when nothing changed, "call_k1k2" and
/// "call_k3" on a 3×3 grid. Every sample follows an untimed call on the same input (uploads,
/// recording and compilation happen there) and times calls_per_sample calls. Interleaved: for
/// each size, for each repeat, for each kernel, for each backend. A field of random values on a
/// 64³ grid over [-1.1, 1.1]³ is set once per backend.
std::vector<KernelBenchResult> bench_kernels(const std::vector<BenchBackend>& backends,
                                             const KernelBenchOptions& options);

// ---------------------------------------------------------------------------------------------
// Reports

/// The median (mean of the middle two for an even count). \pre !values.empty().
double median(std::vector<double> values);

/// The JSON written by --json: {"version", "repeat", "stop_after", "backends": {key: {"name",
/// "startup_seconds"} or {"unavailable"}}, "results": [per (scene, backend): "scene", "backend",
/// "backend_name", "runs", ["error"], "coarse_triangles", "refined_triangles", "iterations",
/// "final_energy" (median), "samples_final_energy", "median_seconds" and "samples_seconds" (by
/// stage: setup, refine, pieces, animate, total; stages that ran), ["to_cpu"] (ratios of
/// medians by stage), "paper_seconds", "paper_triangles", "refine_to_paper"], "comparisons": [per
/// compare_backends() entry: "scene", "backend", "triangles_cpu", "triangles_<backend>",
/// "triangle_difference", "triangle_relative_difference", "energy_cpu", "energy_<backend>",
/// "energy_relative_difference", "setup_refine_ratio", "setup_refine_ratios", "total_ratio"],
/// "kernels": [per (kernel, size, backend): median_ms, samples_ms, ...], "notes": [...]}.
/// Missing figures are null.
nlohmann::ordered_json bench_json(const std::vector<SceneBenchResult>& scenes,
                                  const std::vector<KernelBenchResult>& kernels,
                                  const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                                  const std::vector<std::string>& notes);

/// The scene table (empty string when `scenes` is empty): per (scene, backend) the triangles
/// (coarse -> refined), final energy, median seconds of every stage, the paper's triangles and
/// time and refine/paper; then, when there are comparisons, per scene and non-cpu backend the
/// setup+refine and total ratios to cpu and the refined-triangle and energy differences; then
/// the failures and a footer saying how to read it.
std::string scene_table(const std::vector<SceneBenchResult>& scenes, int repeat, Stage stop_after);
/// The kernel table (empty string when `kernels` is empty).
std::string kernel_table(const std::vector<KernelBenchResult>& kernels, const std::vector<BenchBackend>& backends);

/// What the Markdown report says about where and how it was measured.
struct BenchMarkdownContext {
  std::string command;              ///< the command line of the run, shown verbatim
  unsigned hardware_threads = 0;    ///< of the machine; 0 = not known
};

/// The kind of device a backend ran on, the heading of its table in docs/PERFORMANCE.md:
/// "CPU backend, N threads" for "cpu" and "cpu:N" (N = BenchBackend::threads, or
/// default_threads() when that is 0); for "vulkan" "lavapipe (<device>)" when its device is Mesa's
/// llvmpipe, else "GPU (<device>)", <device> taken from the name "vulkan (<device>)"; the key and
/// "(unavailable)" when it did not start.
std::string backend_kind(const BenchBackend& backend);

/// The run as GitHub-flavoured Markdown, the section docs/PERFORMANCE.md keeps per machine:
/// a "## " heading naming the backends' kinds, a line with fracref's version, `context.command`,
/// the repeat count and the last stage; then per backend, in `backends` order, a "### " heading
/// (backend_kind()) and a table of its scenes (scene, triangles coarse → refined, stop, E ratio,
/// weak fraction, median seconds of every stage, the paper's triangles and seconds,
/// refine/paper), or the reason it was unavailable; then, when a backend was compared with cpu,
/// a table of the comparisons; then the kernel table (ms per call per backend and the ratios to
/// cpu); then the failures and notes as a list. Cells hold no '|' (escaped) and no newline; a
/// figure that is missing is "-". Nothing is measured here: the same results give the same text.
std::string bench_markdown(const std::vector<SceneBenchResult>& scenes, const std::vector<KernelBenchResult>& kernels,
                           const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                           const std::vector<std::string>& notes, const BenchMarkdownContext& context);

}  // namespace fracref
