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
};

/// Reports progress: what runs now and the fraction of all runs done.
using BenchProgress = std::function<void(const std::string& what, double fraction)>;

// ---------------------------------------------------------------------------------------------
// Scenes

struct BenchScene {
  std::string name;                 ///< "wall"
  std::filesystem::path scene_file;
  std::uint64_t paper_coarse_triangles = 0;   ///< the paper's counts (demo_scene_targets()); 0 = unknown
  std::uint64_t paper_refined_triangles = 0;
};

/// The measurements of one (scene, backend) pair: one entry per run in every series.
struct SceneBenchResult {
  std::string scene, backend;       ///< backend key
  std::string backend_name;         ///< ComputeBackend::name()
  std::string error;                ///< why the runs stopped (unavailable backend or a failure)
  std::vector<double> setup, refine, pieces, total;  ///< seconds from each run's report
  std::optional<std::uint64_t> coarse_triangles, refined_triangles;
  std::optional<std::uint64_t> iterations;
  std::uint64_t paper_coarse_triangles = 0, paper_refined_triangles = 0;  ///< from BenchScene
};

struct SceneBenchOptions {
  int repeat = 3;
  Stage stop_after = Stage::refine;
  std::filesystem::path scratch;    ///< an existing folder for the runs' outputs (each removed after)
  BenchProgress progress;
};

/// Runs every (scene, backend) pair options.repeat times, interleaved: for each repeat, for each
/// scene, for each backend. Each run goes through run_job into its own folder under
/// options.scratch, removed afterwards; the seconds are the job's own (report.json). A pair
/// whose run throws records the message and runs no more. Results in scene-major order.
std::vector<SceneBenchResult> bench_scenes(const std::vector<BenchScene>& scenes,
                                           const std::vector<BenchBackend>& backends,
                                           const SceneBenchOptions& options);

/// The paper's time for a demo scene (seconds, one i7-2600 core), or nullopt.
std::optional<double> paper_seconds(const std::string& scene);

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

/// The JSON written by --json: {"version", "repeat", "stop_after", "backends": {key: {"name"} or
/// {"unavailable"}}, "results": [per (scene, backend): medians, samples, counts, paper ratio,
/// vulkan_to_cpu], "kernels": [per (kernel, size, backend): median_ms, samples_ms, ...],
/// "notes": [...]}.
nlohmann::ordered_json bench_json(const std::vector<SceneBenchResult>& scenes,
                                  const std::vector<KernelBenchResult>& kernels,
                                  const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                                  const std::vector<std::string>& notes);

/// The scene table (empty string when `scenes` is empty), with its footer.
std::string scene_table(const std::vector<SceneBenchResult>& scenes, int repeat, Stage stop_after);
/// The kernel table (empty string when `kernels` is empty).
std::string kernel_table(const std::vector<KernelBenchResult>& kernels, const std::vector<BenchBackend>& backends);

}  // namespace fracref
