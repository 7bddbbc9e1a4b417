// The files of one job folder: job.json, scene.json, status.json, the report and the log.
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "batch/batch_internal.hpp"
#include "scene/json_strict.hpp"
#include "scene/scene.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref::batch_detail {
namespace fs = std::filesystem;
using nlohmann::json;
namespace {

std::string effective(const std::string& own, const std::string& fallback) { return own.empty() ? fallback : own; }

/// Parses a JSON file leniently (a missing or broken file reads as null): these are our own
/// records, and a broken one only means "not complete".
json read_record(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return nullptr;
  std::stringstream ss;
  ss << in.rdbuf();
  return json::parse(ss.str(), nullptr, false);
}

/// Generates demo `name` once per batch run into OUT/inputs/<name>; a folder left there by an
/// earlier or concurrent run is reused (it only ever appears complete, by a rename).
fs::path demo_scene(const std::string& name, const BatchRunOptions& options, DemoScenes& demos) {
  if (auto it = demos.find(name); it != demos.end()) return it->second;
  if (!options.generate_demo) throw RunError("batch: demo '" + name + "' with scene overrides needs the scene generator");
  const fs::path target = options.out / "inputs" / name;
  const fs::path scene = target / (name + ".json");
  if (!fs::exists(scene)) {
    const fs::path staging = options.out / "inputs" / (name + ".tmp-" + std::to_string(::getpid()));
    fs::remove_all(staging);
    fs::create_directories(staging);
    options.generate_demo(name, staging);
    std::error_code ec;
    fs::rename(staging, target, ec);
    if (ec) fs::remove_all(staging);  // another run renamed its copy first
    if (!fs::exists(scene)) throw RunError(scene.string() + ": the generated demo scene is missing");
  }
  return demos[name] = scene;
}

/// Writes folder/scene.json: `source` with the overrides applied and its paths anchored to its
/// own folder, checked by loading both (so an override error names the original scene file).
fs::path write_overridden_scene(const fs::path& source, const BatchJob& job, const fs::path& folder) {
  json scene = read_json_file(source);
  apply_overrides(scene, job.overrides, source.string());
  const Scene expected = parse_scene(scene, source);
  anchor_scene_paths(scene, source.parent_path(), expected.name);
  const fs::path file = folder / "scene.json";
  write_file_atomic(file, scene.dump(2) + "\n");
  const Scene written = load_scene(file);
  if (written.exterior != expected.exterior || written.fracture.mesh != expected.fracture.mesh ||
      written.fracture.files != expected.fracture.files || written.fracture.cracks != expected.fracture.cracks ||
      written.animation.frames != expected.animation.frames || written.field.file != expected.field.file ||
      written.animation.parent_map != expected.animation.parent_map ||
      written.animation.transforms != expected.animation.transforms || written.name != expected.name)
    throw RunError(file.string() + ": the rewritten scene does not refer to the same files as " + source.string());
  return file;
}

}  // namespace

json job_spec(const BatchJob& job, const BatchRunOptions& options) {
  json overrides = json::object();
  for (const auto& [k, v] : job.overrides) overrides[k] = v;
  return {{"id", job.id},
          {"scene", job.demo.empty() ? job.scene.string() : ""},
          {"demo", job.demo},
          {"seed", job.seed ? json(*job.seed) : json(nullptr)},
          {"stop_after", effective(job.stop_after, options.stop_after)},
          {"backend", effective(job.backend, options.backend)},
          {"overrides", overrides}};
}

bool is_complete(const fs::path& folder, const json& spec) {
  const json report = read_record(folder / "output" / "report.json");
  if (!report.is_object() || !report.contains("seconds") || !report["seconds"].is_object() ||
      !report["seconds"].contains("total"))
    return false;
  return read_record(folder / "job.json") == spec;
}

std::vector<std::string> job_command(const BatchJob& job, const BatchRunOptions& options, const fs::path& folder,
                                     DemoScenes& demos) {
  std::vector<std::string> args{options.exe.string()};
  if (!job.demo.empty() && job.overrides.empty()) {
    args.insert(args.end(), {"demo", job.demo});
  } else {
    const fs::path source = job.demo.empty() ? job.scene : demo_scene(job.demo, options, demos);
    const fs::path scene = job.overrides.empty() ? source : write_overridden_scene(source, job, folder);
    args.insert(args.end(), {"refine", scene.string()});
  }
  args.insert(args.end(), {"-o", (folder / "output").string(), "--backend", effective(job.backend, options.backend)});
  const std::string stop = effective(job.stop_after, options.stop_after);
  if (!stop.empty()) args.insert(args.end(), {"--stop-after", stop});
  if (job.seed) args.insert(args.end(), {"--seed", std::to_string(*job.seed)});
  if (options.threads > 0) args.insert(args.end(), {"--threads", std::to_string(options.threads)});
  return args;
}

void read_report(const fs::path& folder, JobOutcome& outcome) {
  const json report = read_record(folder / "output" / "report.json");
  if (!report.is_object()) return;
  auto count = [&](const char* key) -> std::optional<std::uint64_t> {
    if (report.contains(key) && report[key].is_number_unsigned()) return report[key].get<std::uint64_t>();
    return std::nullopt;
  };
  outcome.coarse_triangles = count("coarse_triangles");
  outcome.refined_triangles = count("refined_triangles");
  if (report.contains("seconds") && report["seconds"].is_object() && report["seconds"].contains("total") &&
      report["seconds"]["total"].is_number())
    outcome.job_seconds = report["seconds"]["total"].get<double>();
}

JobOutcome recorded_outcome(const fs::path& folder, bool complete) {
  JobOutcome o;
  const json status = read_record(folder / "status.json");
  if (status.is_object()) {
    if (status.contains("seconds") && status["seconds"].is_number()) o.seconds = status["seconds"].get<double>();
    if (!complete) {
      const std::string s = status.value("status", "");
      o.status = s == "failed" ? JobStatus::failed : s == "crashed" ? JobStatus::crashed : JobStatus::pending;
      if (status.contains("exit_code") && status["exit_code"].is_number_integer())
        o.exit_code = status["exit_code"].get<int>();
      if (status.contains("signal") && status["signal"].is_number_integer()) o.signal = status["signal"].get<int>();
      if (status.contains("message") && status["message"].is_string()) o.message = status["message"].get<std::string>();
      if (o.status == JobStatus::pending) o = JobOutcome{};
    }
  }
  if (complete) {
    o.status = JobStatus::skipped;
    o.exit_code = 0;
    read_report(folder, o);
  }
  return o;
}

void write_status(const fs::path& folder, const JobOutcome& o) {
  json j = {{"status", to_string(o.status)},
            {"exit_code", o.exit_code ? json(*o.exit_code) : json(nullptr)},
            {"signal", o.signal},
            {"seconds", o.seconds},
            {"message", o.message}};
  write_file_atomic(folder / "status.json", j.dump(2) + "\n");
}

std::string last_log_line(const fs::path& log) {
  std::ifstream in(log, std::ios::binary);
  std::string line, last;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) last = line;
  }
  if (last.size() > 300) last = last.substr(0, 297) + "...";
  return last;
}

std::string shell_line(const std::vector<std::string>& args) {
  std::string s;
  for (const std::string& a : args) {
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789_-+=./,:@%") == std::string::npos;
    std::string q = a;
    if (!plain) {
      q = "'";
      for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      q += "'";
    }
    if (!s.empty()) s += ' ';
    s += q;
  }
  return s;
}

}  // namespace fracref::batch_detail
