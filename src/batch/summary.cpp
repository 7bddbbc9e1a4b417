// OUT/summary.json and OUT/summary.csv.
#include <cstdio>

#include "batch/runner.hpp"
#include "util/atomic_output.hpp"

namespace fracref {
namespace {

using nlohmann::ordered_json;

template <class T>
ordered_json optional_json(const std::optional<T>& v) {
  return v ? ordered_json(*v) : ordered_json(nullptr);
}

ordered_json overrides_json(const BatchJob& job) {
  ordered_json o = ordered_json::object();
  if (job.seed) o["seed"] = *job.seed;
  if (!job.stop_after.empty()) o["stop_after"] = job.stop_after;
  if (!job.backend.empty()) o["backend"] = job.backend;
  for (const auto& [k, v] : job.overrides) o[k] = v;
  return o;
}

/// RFC 4180: quoted when it holds a comma, a quote or a line break; quotes doubled.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

template <class T>
std::string optional_text(const std::optional<T>& v) {
  if (!v) return "";
  if constexpr (std::is_floating_point_v<T>) return number(*v);
  else return std::to_string(*v);
}

ordered_json summary_json(const Manifest& m, const BatchResult& r) {
  ordered_json counts = ordered_json::object();
  for (JobStatus s : {JobStatus::ok, JobStatus::failed, JobStatus::crashed, JobStatus::skipped, JobStatus::pending})
    counts[to_string(s)] = r.count(s);
  ordered_json jobs = ordered_json::array();
  for (std::size_t i = 0; i < m.jobs.size(); ++i) {
    const BatchJob& j = m.jobs[i];
    const JobOutcome& o = r.jobs[i];
    jobs.push_back({{"id", j.id},
                    {"scene", j.scene_as_written},
                    {"overrides", overrides_json(j)},
                    {"status", to_string(o.status)},
                    {"exit_code", optional_json(o.exit_code)},
                    {"signal", o.signal},
                    {"seconds", o.seconds},
                    {"job_seconds", optional_json(o.job_seconds)},
                    {"coarse_triangles", optional_json(o.coarse_triangles)},
                    {"refined_triangles", optional_json(o.refined_triangles)},
                    {"message", o.message},
                    {"folder", "jobs/" + j.id}});
  }
  return {{"manifest", m.file.string()}, {"success", r.success()}, {"counts", counts}, {"jobs", jobs}};
}

std::string summary_csv(const Manifest& m, const BatchResult& r) {
  std::string csv =
      "id,scene,overrides,status,exit_code,signal,seconds,job_seconds,coarse_triangles,refined_triangles,message\n";
  for (std::size_t i = 0; i < m.jobs.size(); ++i) {
    const BatchJob& j = m.jobs[i];
    const JobOutcome& o = r.jobs[i];
    const std::string fields[] = {j.id,
                                  j.scene_as_written,
                                  j.describe_overrides(),
                                  to_string(o.status),
                                  optional_text(o.exit_code),
                                  o.signal ? std::to_string(o.signal) : "",
                                  o.status == JobStatus::pending ? "" : number(o.seconds),
                                  optional_text(o.job_seconds),
                                  optional_text(o.coarse_triangles),
                                  optional_text(o.refined_triangles),
                                  o.message};
    for (std::size_t f = 0; f < std::size(fields); ++f) {
      if (f) csv += ',';
      csv += csv_field(fields[f]);
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace

void write_batch_summary(const Manifest& manifest, const BatchResult& result, const std::filesystem::path& out) {
  std::filesystem::create_directories(out);
  write_file_atomic(out / "summary.json", summary_json(manifest, result).dump(2) + "\n");
  write_file_atomic(out / "summary.csv", summary_csv(manifest, result));
}

}  // namespace fracref
