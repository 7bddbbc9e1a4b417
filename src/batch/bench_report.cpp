// The bench's JSON and its two tables.
#include <cmath>
#include <cstdio>

#include "batch/bench.hpp"
#include "version.hpp"

namespace fracref {
namespace {

using nlohmann::ordered_json;
using Row = std::vector<std::string>;

/// 3 significant-ish digits without exponents: 1234.5 -> "1234.5", 45.61 -> "45.61", 0.01234 -> "0.0123".
std::string fmt(double v) {
  char buf[32];
  const double a = std::fabs(v);
  const char* f = a >= 100 ? "%.1f" : a >= 1 ? "%.2f" : a >= 0.01 ? "%.3f" : "%.4f";
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string ratio_text(double r) { return fmt(r) + "x"; }

/// Columns padded to their widest cell; the first `left` columns left-aligned, the rest right.
std::string format_table(const std::vector<Row>& rows, std::size_t left) {
  std::vector<std::size_t> width;
  for (const Row& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], r[c].size());
    }
  std::string out;
  for (const Row& r : rows) {
    std::string line;
    for (std::size_t c = 0; c < r.size(); ++c) {
      const std::string pad(width[c] - r[c].size(), ' ');
      if (c) line += "  ";
      line += c < left ? r[c] + pad : pad + r[c];
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

const std::vector<double>* series(const SceneBenchResult& r, const std::string& key) {
  if (key == "setup") return &r.setup;
  if (key == "refine") return &r.refine;
  if (key == "pieces") return &r.pieces;
  return &r.total;
}

std::optional<double> median_of(const std::vector<double>& v) {
  return v.empty() ? std::nullopt : std::optional<double>(median(v));
}

const SceneBenchResult* cpu_result(const std::vector<SceneBenchResult>& all, const SceneBenchResult& r) {
  for (const SceneBenchResult& c : all)
    if (c.scene == r.scene && c.backend == "cpu") return &c;
  return nullptr;
}

const KernelBenchResult* cpu_kernel(const std::vector<KernelBenchResult>& all, const KernelBenchResult& k) {
  for (const KernelBenchResult& c : all)
    if (c.kernel == k.kernel && c.size == k.size && c.backend == "cpu") return &c;
  return nullptr;
}

ordered_json scene_json(const std::vector<SceneBenchResult>& all, const SceneBenchResult& r) {
  ordered_json j = {{"scene", r.scene}, {"backend", r.backend}, {"backend_name", r.backend_name}, {"runs", r.total.size()}};
  if (!r.error.empty()) j["error"] = r.error;
  auto put = [&](const char* key, const std::optional<std::uint64_t>& v) { j[key] = v ? ordered_json(*v) : ordered_json(); };
  put("coarse_triangles", r.coarse_triangles);
  put("refined_triangles", r.refined_triangles);
  put("iterations", r.iterations);
  ordered_json med = ordered_json::object(), samples = ordered_json::object(), to_cpu = ordered_json::object();
  const SceneBenchResult* cpu = r.backend == "cpu" ? nullptr : cpu_result(all, r);
  for (const char* key : {"setup", "refine", "pieces", "total"}) {
    const std::vector<double>& s = *series(r, key);
    if (s.empty()) continue;
    med[key] = median(s);
    samples[key] = s;
    if (cpu && !series(*cpu, key)->empty()) to_cpu[key] = median(s) / median(*series(*cpu, key));
  }
  j["median_seconds"] = med;
  j["samples_seconds"] = samples;
  if (cpu) j["to_cpu"] = to_cpu;
  const std::optional<double> paper = paper_seconds(r.scene);
  j["paper_seconds"] = paper ? ordered_json(*paper) : ordered_json();
  j["paper_triangles"] = r.paper_refined_triangles
                             ? ordered_json{{"coarse", r.paper_coarse_triangles}, {"refined", r.paper_refined_triangles}}
                             : ordered_json();
  j["refine_to_paper"] = paper && !r.refine.empty() ? ordered_json(median(r.refine) / *paper) : ordered_json();
  return j;
}

ordered_json kernel_json(const std::vector<KernelBenchResult>& all, const KernelBenchResult& k) {
  ordered_json j = {{"kernel", k.kernel}, {"size", k.size}, {"backend", k.backend}};
  if (!k.error.empty()) j["error"] = k.error;
  j["median_ms"] = k.ms.empty() ? ordered_json() : ordered_json(median(k.ms));
  j["samples_ms"] = k.ms;
  j["calls_per_sample"] = k.calls_per_sample;
  if (k.backend != "cpu") {
    const KernelBenchResult* cpu = cpu_kernel(all, k);
    j["to_cpu"] = cpu && !cpu->ms.empty() && !k.ms.empty() ? ordered_json(median(k.ms) / median(cpu->ms)) : ordered_json();
  }
  return j;
}

std::string size_label(const KernelBenchResult& k) {
  const auto side = std::size_t(std::llround(std::cbrt(double(k.size))));
  if (k.kernel == "pyramid" && side * side * side == k.size) return std::to_string(side) + "^3 grid";
  return std::to_string(k.size);
}

}  // namespace

ordered_json bench_json(const std::vector<SceneBenchResult>& scenes, const std::vector<KernelBenchResult>& kernels,
                        const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                        const std::vector<std::string>& notes) {
  ordered_json b = ordered_json::object();
  for (const BenchBackend& be : backends)
    b[be.key] = be.backend ? ordered_json{{"name", be.backend->name()}} : ordered_json{{"unavailable", be.unavailable}};
  ordered_json results = ordered_json::array(), ks = ordered_json::array();
  for (const SceneBenchResult& r : scenes) results.push_back(scene_json(scenes, r));
  for (const KernelBenchResult& k : kernels) ks.push_back(kernel_json(kernels, k));
  return {{"version", kVersion}, {"repeat", repeat},     {"stop_after", to_string(stop_after)},
          {"backends", b},       {"results", results}, {"kernels", ks},
          {"notes", notes}};
}

std::string scene_table(const std::vector<SceneBenchResult>& scenes, int repeat, Stage stop_after) {
  if (scenes.empty()) return "";
  std::vector<Row> rows = {{"scene", "backend", "triangles", "setup s", "refine s", "pieces s", "total s", "vs cpu",
                            "paper triangles", "paper s", "refine/paper"}};
  std::vector<std::string> errors;
  for (const SceneBenchResult& r : scenes) {
    Row row = {r.scene, r.backend};
    std::string triangles = r.coarse_triangles ? std::to_string(*r.coarse_triangles) : "-";
    if (r.refined_triangles) triangles += " -> " + std::to_string(*r.refined_triangles);
    row.push_back(triangles);
    for (const char* key : {"setup", "refine", "pieces", "total"}) {
      const std::optional<double> m = median_of(*series(r, key));
      row.push_back(m ? fmt(*m) : "-");
    }
    const SceneBenchResult* cpu = r.backend == "cpu" ? nullptr : cpu_result(scenes, r);
    row.push_back(cpu && !cpu->total.empty() && !r.total.empty() ? ratio_text(median(r.total) / median(cpu->total)) : "-");
    row.push_back(r.paper_refined_triangles ? std::to_string(r.paper_coarse_triangles) + " -> " +
                                                  std::to_string(r.paper_refined_triangles)
                                            : "-");
    const std::optional<double> paper = paper_seconds(r.scene);
    row.push_back(paper ? fmt(*paper) : "-");
    row.push_back(paper && !r.refine.empty() ? ratio_text(median(r.refine) / *paper) : "-");
    rows.push_back(row);
    if (!r.error.empty()) errors.push_back(r.scene + " on " + r.backend + ": " + r.error);
  }
  std::string out = format_table(rows, 3);
  for (const std::string& e : errors) out += "  ! " + e + "\n";
  out += "Medians of " + std::to_string(repeat) + (repeat == 1 ? " run" : " runs") + ", interleaved (repeat, scene, backend); seconds are the job's own "
         "(report.json). vs cpu: total / the cpu total.\n";
  if (stop_after == Stage::refine)
    out += "Stopped after refine: the pieces and animate stages are not robust yet (--stop-after pieces includes pieces).\n";
  else
    out += std::string("Stopped after ") + to_string(stop_after) + ".\n";
  out += "Paper: one core of an i7-2600 (2014), refinement only (its pyramid initialisation took 10-30 s more); "
         "refine/paper compares our refine median with it, whatever triangle counts each reached.\n";
  return out;
}

std::string kernel_table(const std::vector<KernelBenchResult>& kernels, const std::vector<BenchBackend>& backends) {
  if (kernels.empty()) return "";
  Row header = {"kernel", "size"};
  for (const BenchBackend& b : backends) header.push_back(b.key + " ms");
  for (const BenchBackend& b : backends)
    if (b.key != "cpu") header.push_back(b.key + "/cpu");
  std::vector<Row> rows = {header};
  std::vector<std::string> errors;
  for (std::size_t i = 0; i < kernels.size(); i += backends.size()) {
    Row row = {kernels[i].kernel, size_label(kernels[i])};
    for (std::size_t b = 0; b < backends.size() && i + b < kernels.size(); ++b) {
      const KernelBenchResult& k = kernels[i + b];
      row.push_back(k.ms.empty() ? "n/a" : fmt(median(k.ms)));
      if (!k.error.empty() && (backends[b].backend || i == 0)) errors.push_back(k.kernel + " on " + k.backend + ": " + k.error);
    }
    for (std::size_t b = 0; b < backends.size() && i + b < kernels.size(); ++b) {
      if (backends[b].key == "cpu") continue;
      const KernelBenchResult& k = kernels[i + b];
      const KernelBenchResult* cpu = cpu_kernel(kernels, k);
      row.push_back(cpu && !cpu->ms.empty() && !k.ms.empty() ? ratio_text(median(k.ms) / median(cpu->ms)) : "-");
    }
    rows.push_back(row);
  }
  std::string out = format_table(rows, 2);
  for (const std::string& e : errors) out += "  ! " + e + "\n";
  out += "ms per call, medians, interleaved; call_*: the fixed cost of a call on 9 vertices with nothing changed; "
         "pyramid: 5 levels.\n";
  return out;
}

}  // namespace fracref
