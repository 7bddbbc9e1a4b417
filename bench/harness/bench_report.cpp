// The bench's JSON, its two text tables and its Markdown report.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "harness/bench.hpp"
#include "util/parallel.hpp"
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

/// 6 significant digits: energies are compared between backends, seconds are not.
std::string energy_text(double e) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", e);
  return buf;
}

/// A signed percentage with 2 decimals below 10 %, e.g. "+0.57%", "-12.3%", "+0.00%".
std::string percent_text(double fraction) {
  char buf[32];
  const double p = 100.0 * fraction;
  std::snprintf(buf, sizeof buf, std::fabs(p) < 10.0 ? "%+.2f%%" : "%+.1f%%", p);
  return buf;
}

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

const char* const kStages[] = {"setup", "refine", "kernels", "pieces", "animate", "total"};

const std::vector<double>* series(const SceneBenchResult& r, const std::string& key) {
  if (key == "setup") return &r.setup;
  if (key == "refine") return &r.refine;
  if (key == "kernels") return &r.kernels;
  if (key == "pieces") return &r.pieces;
  if (key == "animate") return &r.animate;
  return &r.total;
}

template <class T>
ordered_json or_null(const std::optional<T>& v) {
  return v ? ordered_json(*v) : ordered_json();
}

/// "+12 (+0.57%)", "+0 (+0.00%)"; without the percentage when `rel` is missing; "-" without `d`.
std::string difference_text(const std::optional<std::int64_t>& d, const std::optional<double>& rel) {
  if (!d) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+lld", static_cast<long long>(*d));
  return rel ? std::string(buf) + " (" + percent_text(*rel) + ")" : std::string(buf);
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
  j["coarse_triangles"] = or_null(r.coarse_triangles);
  j["refined_triangles"] = or_null(r.refined_triangles);
  j["iterations"] = or_null(r.iterations);
  j["stop_reason"] = or_null(r.stop_reason);
  j["energy_ratio"] = or_null(r.energy_ratio);
  j["weak_fraction"] = {{"coarse", or_null(r.weak_coarse)}, {"refined", or_null(r.weak_refined)},
                        {"reachable", or_null(r.weak_reachable)}};
  j["final_energy"] = or_null(median_of(r.final_energy));
  j["samples_final_energy"] = r.final_energy;
  ordered_json med = ordered_json::object(), samples = ordered_json::object(), to_cpu = ordered_json::object();
  const SceneBenchResult* cpu = r.backend == "cpu" ? nullptr : cpu_result(all, r);
  for (const char* key : kStages) {
    const std::vector<double>& s = *series(r, key);
    if (s.empty()) continue;
    med[key] = median(s);
    samples[key] = s;
    if (cpu && !series(*cpu, key)->empty()) to_cpu[key] = median(s) / median(*series(*cpu, key));
  }
  j["median_seconds"] = med;
  j["samples_seconds"] = samples;
  if (cpu) j["to_cpu"] = to_cpu;
  const bool paper = r.paper_seconds > 0.0;
  j["paper_seconds"] = paper ? ordered_json(r.paper_seconds) : ordered_json();
  j["paper_triangles"] = r.paper_refined_triangles
                             ? ordered_json{{"coarse", r.paper_coarse_triangles}, {"refined", r.paper_refined_triangles}}
                             : ordered_json();
  j["refine_to_paper"] = paper && !r.refine.empty() ? ordered_json(median(r.refine) / r.paper_seconds) : ordered_json();
  return j;
}

ordered_json comparison_json(const SceneComparison& c) {
  return {{"scene", c.scene},
          {"backend", c.backend},
          {"triangles_cpu", or_null(c.triangles_cpu)},
          {"triangles_" + c.backend, or_null(c.triangles_other)},
          {"triangle_difference", or_null(c.triangle_difference)},
          {"triangle_relative_difference", or_null(c.triangle_relative_difference)},
          {"energy_cpu", or_null(c.energy_cpu)},
          {"energy_" + c.backend, or_null(c.energy_other)},
          {"energy_relative_difference", or_null(c.energy_relative_difference)},
          {"setup_refine_ratio", or_null(c.setup_refine_ratio)},
          {"setup_refine_ratios", c.setup_refine_ratios},
          {"total_ratio", or_null(c.total_ratio)}};
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

Row scene_row(const SceneBenchResult& r) {
  Row row = {r.scene, r.backend};
  std::string triangles = r.coarse_triangles ? std::to_string(*r.coarse_triangles) : "-";
  if (r.refined_triangles) triangles += " -> " + std::to_string(*r.refined_triangles);
  row.push_back(triangles);
  const std::optional<double> energy = median_of(r.final_energy);
  row.push_back(energy ? energy_text(*energy) : "-");
  row.push_back(r.stop_reason.value_or("-"));
  row.push_back(r.energy_ratio ? fmt(*r.energy_ratio) : "-");
  std::string weak = r.weak_coarse && r.weak_refined ? fmt(*r.weak_coarse) + " -> " + fmt(*r.weak_refined) : "-";
  if (r.weak_reachable) weak += " (reach " + fmt(*r.weak_reachable) + ")";
  row.push_back(weak);
  for (const char* key : kStages) {
    const std::optional<double> m = median_of(*series(r, key));
    row.push_back(m ? fmt(*m) : "-");
  }
  row.push_back(r.paper_refined_triangles
                    ? std::to_string(r.paper_coarse_triangles) + " -> " + std::to_string(r.paper_refined_triangles)
                    : "-");
  const bool paper = r.paper_seconds > 0.0;
  row.push_back(paper ? fmt(r.paper_seconds) : "-");
  row.push_back(paper && !r.refine.empty() ? ratio_text(median(r.refine) / r.paper_seconds) : "-");
  return row;
}

/// The comparison table's rows, header first.
std::vector<Row> comparison_rows(const std::vector<SceneComparison>& comparisons) {
  std::vector<Row> rows = {{"scene", "vs cpu", "setup+refine", "total", "refined triangles", "final energy"}};
  for (const SceneComparison& c : comparisons)
    rows.push_back({c.scene, c.backend, c.setup_refine_ratio ? ratio_text(*c.setup_refine_ratio) : "-",
                    c.total_ratio ? ratio_text(*c.total_ratio) : "-",
                    difference_text(c.triangle_difference, c.triangle_relative_difference),
                    c.energy_relative_difference ? percent_text(*c.energy_relative_difference) : "-"});
  return rows;
}

/// "vulkan 0.41 s, cpu 0.0001 s": each available backend's start-up, in the results' order.
std::string startup_text(const std::vector<SceneBenchResult>& scenes) {
  std::vector<std::string> seen;
  std::string out;
  for (const SceneBenchResult& r : scenes) {
    if (r.error.rfind("unavailable: ", 0) == 0 || std::find(seen.begin(), seen.end(), r.backend) != seen.end()) continue;
    seen.push_back(r.backend);
    out += (out.empty() ? "" : ", ") + r.backend + " " + fmt(r.startup_seconds) + " s";
  }
  return out;
}

std::string medians_text(int repeat) {
  return "Medians of " + std::to_string(repeat) + (repeat == 1 ? " run" : " runs") +
         ", interleaved (repeat, scene, backend); seconds are the job's own (report.json), - where a "
         "stage did not run; final energy: after the last refine iteration.";
}

std::string comparison_text(const std::vector<SceneBenchResult>& scenes) {
  return "vs cpu: setup+refine = median over paired runs of (setup + refine + backend start-up) / the same on "
         "cpu (start-up, median of 5 creations: " + startup_text(scenes) + "); total = median total / cpu median total; "
         "refined triangles = backend - cpu (relative to cpu); final energy = (backend - cpu) / |cpu|.";
}

const char* const kPaperText =
    "Paper: one core of an i7-2600 (2014), refinement only (its pyramid initialisation took 10-30 s more); "
    "refine/paper compares our refine median with it, whatever triangle counts each reached.";

const char* const kKernelText =
    "ms per call, medians, interleaved; call_*: the fixed cost of a call on 9 vertices with nothing changed; "
    "pyramid: 5 levels.";

std::string scene_footer(const std::vector<SceneBenchResult>& scenes, int repeat, Stage stop_after, bool compared) {
  std::string out = medians_text(repeat) + "\n";
  if (compared) out += comparison_text(scenes) + "\n";
  if (stop_after != Stage::animate) out += std::string("Stopped after ") + to_string(stop_after) + ".\n";
  return out + kPaperText + "\n";
}

const Row kSceneHeader = {"scene", "backend", "triangles", "final energy", "stop", "E ratio", "weak fraction",
                          "setup s", "refine s", "kernels s", "pieces s", "animate s", "total s", "paper triangles",
                          "paper s", "refine/paper"};

/// The kernel table's rows, header first; the failures met go to `errors`.
std::vector<Row> kernel_rows(const std::vector<KernelBenchResult>& kernels, const std::vector<BenchBackend>& backends,
                             std::vector<std::string>& errors) {
  Row header = {"kernel", "size"};
  for (const BenchBackend& b : backends) header.push_back(b.key + " ms");
  for (const BenchBackend& b : backends)
    if (b.key != "cpu") header.push_back(b.key + "/cpu");
  std::vector<Row> rows = {header};
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
  return rows;
}

/// Text on one line: line breaks as spaces.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

/// A Markdown cell: '|' escaped, line breaks as spaces, " -> " as an arrow.
std::string markdown_cell(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 4, " -> ") == 0) {
      out += " → ";
      i += 3;
    } else if (text[i] == '|') {
      out += "\\|";
    } else {
      out += text[i] == '\n' || text[i] == '\r' ? ' ' : text[i];
    }
  }
  return out;
}

/// A Markdown table: the first row is the header; the first `left` columns left-aligned, the
/// rest right-aligned; short rows padded with empty cells.
std::string markdown_table(const std::vector<Row>& rows, std::size_t left) {
  if (rows.empty()) return "";
  const std::size_t columns = rows.front().size();
  auto line = [&](const Row& r) {
    std::string s = "|";
    for (std::size_t c = 0; c < columns; ++c) {
      s += ' ';
      if (c < r.size()) s += markdown_cell(r[c]);
      s += " |";
    }
    return s + "\n";
  };
  std::string out = line(rows.front()) + "|";
  for (std::size_t c = 0; c < columns; ++c) out += c < left ? "---|" : "---:|";
  out += "\n";
  for (std::size_t i = 1; i < rows.size(); ++i) out += line(rows[i]);
  return out;
}

}  // namespace

ordered_json bench_json(const std::vector<SceneBenchResult>& scenes, const std::vector<KernelBenchResult>& kernels,
                        const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                        const std::vector<std::string>& notes) {
  ordered_json b = ordered_json::object();
  for (const BenchBackend& be : backends)
    b[be.key] = be.backend ? ordered_json{{"name", be.backend->name()}, {"startup_seconds", be.startup_seconds}}
                           : ordered_json{{"unavailable", be.unavailable}};
  ordered_json results = ordered_json::array(), comparisons = ordered_json::array(), ks = ordered_json::array();
  for (const SceneBenchResult& r : scenes) results.push_back(scene_json(scenes, r));
  for (const SceneComparison& c : compare_backends(scenes)) comparisons.push_back(comparison_json(c));
  for (const KernelBenchResult& k : kernels) ks.push_back(kernel_json(kernels, k));
  return {{"version", kVersion},   {"repeat", repeat},   {"stop_after", to_string(stop_after)},
          {"backends", b},         {"results", results}, {"comparisons", comparisons},
          {"kernels", ks},         {"notes", notes}};
}

std::string scene_table(const std::vector<SceneBenchResult>& scenes, int repeat, Stage stop_after) {
  if (scenes.empty()) return "";
  std::vector<Row> rows = {kSceneHeader};
  std::vector<std::string> errors;
  for (const SceneBenchResult& r : scenes) {
    rows.push_back(scene_row(r));
    if (!r.error.empty()) errors.push_back(r.scene + " on " + r.backend + ": " + r.error);
  }
  std::string out = format_table(rows, 3);
  const std::vector<SceneComparison> comparisons = compare_backends(scenes);
  if (!comparisons.empty()) out += "\n", out += format_table(comparison_rows(comparisons), 2);
  for (const std::string& e : errors) out += "  ! " + e + "\n";
  return out + scene_footer(scenes, repeat, stop_after, !comparisons.empty());
}

std::string kernel_table(const std::vector<KernelBenchResult>& kernels, const std::vector<BenchBackend>& backends) {
  if (kernels.empty()) return "";
  std::vector<std::string> errors;
  std::string out = format_table(kernel_rows(kernels, backends, errors), 2);
  for (const std::string& e : errors) out += "  ! " + e + "\n";
  return out + kKernelText + "\n";
}

std::string backend_kind(const BenchBackend& backend) {
  if (!backend.backend) return backend.key + " (unavailable)";
  if (backend.key != "vulkan") {
    const int threads = backend.threads > 0 ? backend.threads : default_threads();
    return "CPU backend, " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
  }
  std::string device = backend.backend->name();
  const std::string prefix = "vulkan (";
  if (device.rfind(prefix, 0) == 0 && device.size() > prefix.size() && device.back() == ')')
    device = device.substr(prefix.size(), device.size() - prefix.size() - 1);
  const bool lavapipe = device.find("llvmpipe") != std::string::npos || device.find("lavapipe") != std::string::npos;
  return (lavapipe ? "lavapipe (" : "GPU (") + device + ")";
}

std::string bench_markdown(const std::vector<SceneBenchResult>& scenes, const std::vector<KernelBenchResult>& kernels,
                           const std::vector<BenchBackend>& backends, int repeat, Stage stop_after,
                           const std::vector<std::string>& notes, const BenchMarkdownContext& context) {
  std::string heading;
  for (const BenchBackend& b : backends) heading += (heading.empty() ? "" : "; ") + backend_kind(b);
  std::string out = "## " + (heading.empty() ? std::string("no backend") : heading) + "\n\n";
  out += std::string("fracref ") + kVersion;
  if (!context.command.empty()) out += ", `" + one_line(context.command) + "`";
  if (context.hardware_threads > 0)
    out += ", on a machine with " + std::to_string(context.hardware_threads) + " hardware threads";
  out += ".";
  if (!scenes.empty()) {
    out += " " + medians_text(repeat);
    if (stop_after != Stage::animate) out += std::string(" Stopped after ") + to_string(stop_after) + ".";
  }
  out += "\n";
  std::vector<std::string> failures;
  for (const BenchBackend& b : backends) {
    out += "\n### " + backend_kind(b) + "\n\n";
    if (!b.backend) {
      out += "Unavailable: " + one_line(b.unavailable) + "\n";
      continue;
    }
    std::vector<Row> rows;
    for (const SceneBenchResult& r : scenes) {
      if (r.backend != b.key) continue;
      Row row = scene_row(r);
      row.erase(row.begin() + 1);  // the backend: the heading says it
      rows.push_back(row);
      if (!r.error.empty()) failures.push_back(r.scene + " on " + r.backend + ": " + r.error);
    }
    if (rows.empty()) {
      out += "No scene was run on it.\n";
      continue;
    }
    Row header = kSceneHeader;
    header.erase(header.begin() + 1);
    rows.insert(rows.begin(), header);
    out += markdown_table(rows, 2);
  }
  if (!scenes.empty()) out += std::string("\n") + kPaperText + "\n";
  const std::vector<SceneComparison> comparisons = compare_backends(scenes);
  if (!comparisons.empty())
    out += "\n### Against the CPU backend\n\n" + markdown_table(comparison_rows(comparisons), 2) + "\n" +
           comparison_text(scenes) + "\n";
  if (!kernels.empty())
    out += "\n### Kernels\n\n" + markdown_table(kernel_rows(kernels, backends, failures), 2) + "\n" + kKernelText + "\n";
  if (!failures.empty() || !notes.empty()) {
    out += "\n";
    for (const std::string& f : failures) out += "- failed: " + one_line(f) + "\n";
    for (const std::string& n : notes) out += "- " + one_line(n) + "\n";
  }
  return out;
}

}  // namespace fracref
