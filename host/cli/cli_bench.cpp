// `fracref bench`: the paper's scenes and the kernels on the CPU and Vulkan backends, as tables
// on stdout and, with --json and --markdown, files (bench/harness/bench.hpp has what is measured
// and how; the Markdown is the section docs/PERFORMANCE.md keeps per machine).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "cli.hpp"
#include "cli_progress.hpp"
#include "harness/bench.hpp"
#include "scenegen/scenegen.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"
#include "vk_backend.hpp"

namespace fracref::cli {
namespace fs = std::filesystem;
namespace {

struct BenchCliOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> backends = {"cpu", "vulkan"};
  std::vector<std::string> threads;  ///< extra CPU rows: thread counts, or "all"
  int repeat = 3;
  std::string json;
  std::string markdown;
  std::string stop_after = "animate";
  bool kernels_only = false;
  bool no_kernels = false;
  std::vector<std::size_t> kernel_sizes = {10'000, 100'000, 1'000'000};
  bool quiet = false;
};

/// The command line that reproduces the run (the options given or their defaults), for the
/// Markdown report.
std::string command_line(const BenchCliOptions& o) {
  auto join = [](const auto& items) {
    std::string s;
    for (const auto& item : items) {
      std::ostringstream one;
      one << item;
      s += (s.empty() ? "" : ",") + one.str();
    }
    return s;
  };
  std::vector<std::string> backends;  // as given: check_options() appends a "cpu:N" per --threads entry
  for (const std::string& b : o.backends)
    if (b.rfind("cpu:", 0) != 0) backends.push_back(b);
  std::string c = "fracref bench";
  if (!o.kernels_only) c += " --scenes " + join(o.scenes);
  c += " --backends " + join(backends);
  if (!o.threads.empty()) c += " --threads " + join(o.threads);
  c += " --repeat " + std::to_string(o.repeat);
  if (!o.kernels_only) c += " --stop-after " + o.stop_after;
  if (o.kernels_only) c += " --kernels-only";
  if (o.no_kernels) c += " --no-kernels";
  if (!o.no_kernels) c += " --kernel-sizes " + join(o.kernel_sizes);
  return c;
}

/// A temporary folder removed with everything in it when the bench ends.
struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("fracref-bench-" + std::to_string(::getpid()));
  ScratchDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// The backends asked for, each with the median seconds of kStartups creations (the first one
/// also pays for loading the driver, and one measurement swings with the machine); one that
/// cannot start is kept, unavailable, with the reason.
constexpr int kStartups = 5;

std::vector<std::unique_ptr<ComputeBackend>> make_backends(const std::vector<std::string>& keys,
                                                           std::vector<BenchBackend>& out) {
  std::vector<std::unique_ptr<ComputeBackend>> owned;
  for (const std::string& key : keys) {
    BenchBackend b{key, nullptr, ""};
    if (key.rfind("cpu:", 0) == 0) b.threads = std::stoi(key.substr(4));
    try {
      std::vector<double> seconds;
      std::unique_ptr<ComputeBackend> made;
      for (int k = 0; k < kStartups; ++k) {
        made.reset();
        const auto t0 = std::chrono::steady_clock::now();
        made = key == "vulkan" ? make_vulkan_backend() : make_cpu_backend(b.threads > 0 ? b.threads : default_threads());
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::nth_element(seconds.begin(), seconds.begin() + kStartups / 2, seconds.end());
      b.startup_seconds = seconds[kStartups / 2];
      owned.push_back(std::move(made));
      b.backend = owned.back().get();
    } catch (const std::exception& e) {
      b.unavailable = e.what();
    }
    out.push_back(b);
  }
  return owned;
}

/// Generates the demo scenes into `folder`; the bunny is skipped, with a note, without its mesh.
std::vector<BenchScene> generate_scenes(const std::vector<std::string>& names, const fs::path& folder,
                                        std::vector<std::string>& notes) {
  std::vector<BenchScene> scenes;
  DemoOptions demo;
  demo.bunny_obj = data_dir() / "bunny.obj";
  for (const std::string& name : names) {
    if (name == "bunny" && !fs::exists(demo.bunny_obj)) {
      notes.push_back("bunny skipped: " + demo.bunny_obj.string() +
                      " is missing (run 'bash .ci/setup build', or set FRACREF_DATA_DIR)");
      continue;
    }
    BenchScene scene{name, generate_demo_scene(name, folder / name, demo)};
    for (const DemoTarget& t : demo_scene_targets())
      if (t.name == name) {
        scene.paper_coarse_triangles = t.coarse_triangles;
        scene.paper_refined_triangles = t.refined_triangles;
        scene.paper_seconds = t.seconds;
      }
    scenes.push_back(scene);
  }
  return scenes;
}

void check_options(BenchCliOptions& o) {
  const std::vector<std::string> known = demo_scene_names();
  if (o.scenes.empty()) o.scenes = known;
  for (const std::string& s : o.scenes)
    if (std::find(known.begin(), known.end(), s) == known.end())
      throw InputError("bench: --scenes: unknown scene '" + s + "' (available: bunny, branch, wall, clay, jello)");
  for (const std::string& b : o.backends)
    if (b != "cpu" && b != "vulkan") throw InputError("bench: --backends: unknown backend '" + b + "' (cpu, vulkan)");
  // Each thread count becomes a CPU backend "cpu:N", compared with "cpu" (every hardware thread).
  for (const std::string& t : o.threads) {
    int n = 0;
    if (t == "all") {
      n = default_threads();
    } else {
      std::size_t used = 0;
      try {
        n = std::stoi(t, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != t.size() || n < 1 || n > 4096)
        throw InputError("bench: --threads: '" + t + "' is not a thread count (1 to 4096) or 'all'");
    }
    o.backends.push_back("cpu:" + std::to_string(n));
  }
  for (std::size_t s : o.kernel_sizes)
    if (s < 4) throw InputError("bench: --kernel-sizes: a size must be at least 4 vertices, got " + std::to_string(s));
}

bool any_failure(const std::vector<SceneBenchResult>& s, const std::vector<KernelBenchResult>& k) {
  auto failed = [](const std::string& e) { return !e.empty() && e.rfind("unavailable: ", 0) != 0; };
  return std::any_of(s.begin(), s.end(), [&](const auto& r) { return failed(r.error); }) ||
         std::any_of(k.begin(), k.end(), [&](const auto& r) { return failed(r.error); });
}

int run_bench(BenchCliOptions o) {
  check_options(o);
  const Stage stop = parse_stage(o.stop_after);
  std::vector<std::string> notes;
  std::vector<BenchBackend> backends;
  const auto owned = make_backends(o.backends, backends);
  for (const BenchBackend& b : backends)
    notes.push_back(b.key + " backend: " + (b.backend ? b.backend->name() : "unavailable: " + b.unavailable));
  ProgressLine line(!o.quiet && stderr_is_terminal());
  ScratchDir scratch;
  std::vector<SceneBenchResult> scenes;
  if (!o.kernels_only) {
    line.update("bench", 0.0, "generating the scenes");
    const std::vector<BenchScene> inputs = generate_scenes(o.scenes, scratch.path / "inputs", notes);
    fs::create_directories(scratch.path / "runs");
    SceneBenchOptions so{o.repeat, stop, scratch.path / "runs", [&](const std::string& w, double f) { line.update("scenes", f, w); }};
    scenes = bench_scenes(inputs, backends, so);
  }
  std::vector<KernelBenchResult> kernels;
  if (!o.no_kernels) {
    KernelBenchOptions ko;
    ko.repeat = o.repeat;
    ko.sizes = o.kernel_sizes;
    ko.progress = [&](const std::string& w, double f) { line.update("kernels", f, w); };
    kernels = bench_kernels(backends, ko);
  }
  line.done();
  std::cout << scene_table(scenes, o.repeat, stop);
  if (!scenes.empty() && !kernels.empty()) std::cout << "\n";
  std::cout << kernel_table(kernels, backends);
  for (const std::string& n : notes) std::cout << "note: " << n << "\n";
  if (!o.json.empty())
    write_file_atomic(o.json, bench_json(scenes, kernels, backends, o.repeat, stop, notes).dump(2) + "\n");
  if (!o.markdown.empty()) {
    const BenchMarkdownContext context{command_line(o), std::thread::hardware_concurrency()};
    write_file_atomic(o.markdown, bench_markdown(scenes, kernels, backends, o.repeat, stop, notes, context));
  }
  return any_failure(scenes, kernels) ? kExitFailure : kExitOk;
}

}  // namespace

void add_bench_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<BenchCliOptions>();
  CLI::App* sub = app.add_subcommand("bench", "Benchmark the CPU and Vulkan backends on the paper's scenes and kernels");
  sub->footer("Runs are interleaved (repeat, scene, backend) and summarised by medians; the machine's speed drifts,\n"
              "so compare backends within one run. Exit code 1 when a run failed (an unavailable backend is not a failure).");
  sub->add_option("--scenes", o->scenes, "demo scenes, comma separated (default: all five)")->delimiter(',');
  sub->add_option("--backends", o->backends, "backends, comma separated: cpu, vulkan (default both)")->delimiter(',');
  sub->add_option("--threads", o->threads,
                  "also run the CPU backend on these thread counts, comma separated, e.g. 1,2,4,all (rows cpu:N, "
                  "compared with cpu on every hardware thread)")
      ->delimiter(',');
  sub->add_option("--repeat", o->repeat, "runs of each measurement (default 3)")->check(CLI::PositiveNumber);
  sub->add_option("--json", o->json, "also write the results as JSON to this file");
  sub->add_option("--markdown", o->markdown,
                  "also write the results as Markdown to this file: the section docs/PERFORMANCE.md keeps per machine");
  sub->add_option("--stop-after", o->stop_after, "last stage of the scene runs (default animate: the whole pipeline)")
      ->check(CLI::IsMember({"preprocess", "refine", "pieces", "animate"}));
  auto* only = sub->add_flag("--kernels-only", o->kernels_only, "skip the scenes");
  sub->add_flag("--no-kernels", o->no_kernels, "skip the kernels")->excludes(only);
  sub->add_option("--kernel-sizes", o->kernel_sizes, "vertex counts of the kernel surfaces (default 10000,100000,1000000)")
      ->delimiter(',');
  sub->add_flag("-q,--quiet", o->quiet, "no progress line");
  sub->callback([o, &action] { action = [o] { return run_bench(*o); }; });
}

}  // namespace fracref::cli
