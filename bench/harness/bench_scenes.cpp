// The scene half of `fracref bench`: whole jobs, interleaved over repeats, scenes and backends.
#include <algorithm>

#include "harness/bench.hpp"
#include "scene/scene.hpp"

namespace fracref {
namespace fs = std::filesystem;
namespace {

using nlohmann::ordered_json;

void add_seconds(const ordered_json& seconds, const char* key, std::vector<double>& to) {
  if (seconds.contains(key) && seconds[key].is_number()) to.push_back(seconds[key].get<double>());
}

std::optional<std::uint64_t> count_of(const ordered_json& report, const char* key) {
  if (report.contains(key) && report[key].is_number_unsigned()) return report[key].get<std::uint64_t>();
  return std::nullopt;
}

/// The energy after the last refine iteration (initial_energy when none ran); nullopt without refine.
std::optional<double> final_energy(const ordered_json& report) {
  if (report.contains("iterations") && report["iterations"].is_array() && !report["iterations"].empty()) {
    const ordered_json& last = report["iterations"].back();
    if (last.contains("energy") && last["energy"].is_number()) return last["energy"].get<double>();
  }
  if (report.contains("initial_energy") && report["initial_energy"].is_number())
    return report["initial_energy"].get<double>();
  return std::nullopt;
}

/// One run of `scene` on `backend` into a fresh folder under `scratch`, recorded in `r`.
void run_once(const Scene& scene, const BenchBackend& backend, const SceneBenchOptions& o, const std::string& tag,
              SceneBenchResult& r) {
  const fs::path out = o.scratch / tag;
  fs::remove_all(out);
  fs::create_directories(out);
  struct Remove {
    fs::path p;
    ~Remove() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } remove{out};
  JobOptions jo;
  jo.stop_after = o.stop_after;
  struct Threads {
    int before = default_threads();
    explicit Threads(int n) {
      if (n > 0) set_default_threads(n);
    }
    ~Threads() { set_default_threads(before); }
  } threads(backend.threads);
  record_run(run_job(scene, out, *backend.backend, jo), r);
}

SceneBenchResult empty_result(const BenchScene& scene, const BenchBackend& b) {
  SceneBenchResult r;
  r.scene = scene.name;
  r.backend = b.key;
  r.paper_coarse_triangles = scene.paper_coarse_triangles;
  r.paper_refined_triangles = scene.paper_refined_triangles;
  r.paper_seconds = scene.paper_seconds;
  r.startup_seconds = b.startup_seconds;
  r.backend_name = b.backend ? b.backend->name() : b.key;
  if (!b.backend) r.error = "unavailable: " + b.unavailable;
  return r;
}

}  // namespace

void record_run(const ordered_json& report, SceneBenchResult& r) {
  static const ordered_json kNone = ordered_json::object();
  const ordered_json& s = report.contains("seconds") && report["seconds"].is_object() ? report["seconds"] : kNone;
  add_seconds(s, "setup", r.setup);
  add_seconds(s, "refine", r.refine);
  add_seconds(s, "kernels", r.kernels);
  add_seconds(s, "pieces", r.pieces);
  add_seconds(s, "animate", r.animate);
  add_seconds(s, "total", r.total);
  if (report.contains("refined_triangles"))
    if (const std::optional<double> e = final_energy(report)) r.final_energy.push_back(*e);
  r.coarse_triangles = count_of(report, "coarse_triangles");
  r.refined_triangles = count_of(report, "refined_triangles");
  r.iterations.reset();
  if (report.contains("iterations") && report["iterations"].is_array()) r.iterations = report["iterations"].size();
  r.stop_reason.reset();
  if (report.contains("stop_reason") && report["stop_reason"].is_string()) r.stop_reason = report["stop_reason"].get<std::string>();
  r.energy_ratio.reset(), r.weak_coarse.reset(), r.weak_refined.reset(), r.weak_reachable.reset();
  auto number = [](const ordered_json& j, const char* key) -> std::optional<double> {
    if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<double>();
    return std::nullopt;
  };
  if (report.contains("quality") && report["quality"].is_object()) {
    const ordered_json& q = report["quality"];
    r.energy_ratio = number(q, "energy_ratio");
    if (q.contains("weak_fraction")) {
      const ordered_json& w = q["weak_fraction"];
      r.weak_coarse = number(w, "coarse"), r.weak_refined = number(w, "refined");
      if (w.is_object() && w.contains("reachable")) r.weak_reachable = number(w["reachable"], "fraction");
    }
  }
}

std::vector<SceneBenchResult> bench_scenes(const std::vector<BenchScene>& scenes, const std::vector<BenchBackend>& backends,
                                           const SceneBenchOptions& o) {
  std::vector<SceneBenchResult> results;
  std::vector<std::optional<Scene>> loaded(scenes.size());
  for (std::size_t s = 0; s < scenes.size(); ++s)
    for (const BenchBackend& b : backends) results.push_back(empty_result(scenes[s], b));
  const std::size_t runs = std::max<std::size_t>(1, std::size_t(o.repeat) * results.size());
  std::size_t done = 0;
  for (int rep = 0; rep < o.repeat; ++rep)
    for (std::size_t s = 0; s < scenes.size(); ++s)
      for (std::size_t b = 0; b < backends.size(); ++b, ++done) {
        SceneBenchResult& r = results[s * backends.size() + b];
        if (!r.error.empty()) continue;
        const std::string tag = scenes[s].name + "-" + backends[b].key + "-" + std::to_string(rep + 1);
        if (o.progress) o.progress(tag, double(done) / double(runs));
        try {
          if (!loaded[s]) loaded[s] = load_scene(scenes[s].scene_file);
          run_once(*loaded[s], backends[b], o, tag, r);
        } catch (const std::exception& e) {
          r.error = e.what();
        }
      }
  if (o.progress) o.progress("scenes done", 1.0);
  return results;
}

}  // namespace fracref
