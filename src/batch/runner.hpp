#pragma once
// Runs the jobs of a manifest as child processes of the fracref binary (`refine` or `demo`), at
// most N at once, each into its own folder, skipping jobs already complete (scenes/BATCH.md).
//
// Job folder OUT/jobs/<id>/:
//   job.json     what the job is (scene, demo, seed, stop_after, backend, overrides): a complete
//                job is skipped only when this matches the manifest's job
//   scene.json   the scene with the job's overrides applied (jobs with scene overrides only)
//   log.txt      the command line, then the child's stdout and stderr
//   status.json  status, exit code or signal, wall seconds, message
//   output/      the job command's output folder (report.json when complete)
// A crash (a signal) or a failure of one job is recorded and the others go on.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/manifest.hpp"

namespace fracref {

enum class JobStatus { ok, failed, crashed, skipped, pending };

/// "ok", "failed", "crashed", "skipped", "pending".
const char* to_string(JobStatus status);

/// What became of one job.
struct JobOutcome {
  JobStatus status = JobStatus::pending;
  std::optional<int> exit_code;  ///< the child's exit code (absent when it was killed or never ran)
  int signal = 0;                ///< the signal that killed it (crashed), else 0
  double seconds = 0.0;          ///< wall seconds of the child (of the earlier run when skipped)
  std::optional<double> job_seconds;  ///< report.json's seconds.total
  std::optional<std::uint64_t> coarse_triangles, refined_triangles;  ///< from report.json
  std::string message;           ///< failed or crashed: why (the last line of its log)
};

/// Counts while the batch runs, for a progress line.
struct BatchProgress {
  std::size_t total = 0;  ///< jobs this run will run or skip
  std::size_t done = 0, running = 0;
  std::size_t ok = 0, failed = 0, crashed = 0, skipped = 0;
};

struct BatchRunOptions {
  std::filesystem::path exe;      ///< the fracref binary run for every job
  std::filesystem::path out;      ///< the batch's output folder (created if missing)
  int parallel = 1;               ///< at most this many jobs at once, >= 1
  std::string backend = "auto";   ///< for jobs that name none
  std::string stop_after;         ///< for jobs that name none; "" = the job command's default
  std::vector<std::string> only;  ///< run only these job ids; empty = every job
  int threads = 0;                ///< worker threads of each job (--threads); 0 = the job's default
  bool summary_only = false;      ///< run nothing; report every job from its folder
  /// Writes demo `name`'s inputs into `folder` and returns its scene file; used for demo jobs
  /// with scene overrides (they run `refine` on the generated scene). Empty: such jobs fail.
  std::function<std::filesystem::path(const std::string& name, const std::filesystem::path& folder)> generate_demo;
  /// Called whenever a job starts or ends. May be empty.
  std::function<void(const BatchProgress&)> progress;
};

struct BatchResult {
  std::vector<JobOutcome> jobs;  ///< one per manifest job, in manifest order
  std::size_t count(JobStatus status) const;
  /// No job failed or crashed.
  bool success() const;
};

/// Runs (or skips, or reports) every job of `manifest`. A job is skipped when its folder holds a
/// complete output (output/report.json with seconds.total) and its job.json matches. Jobs not
/// selected by options.only, and every job when options.summary_only, are reported from their
/// folders: skipped when complete, else their last recorded status, else pending.
/// \throw InputError when options.only names an id the manifest lacks or parallel < 1;
///        RunError when OUT cannot be written.
BatchResult run_batch(const Manifest& manifest, const BatchRunOptions& options);

/// Writes OUT/summary.json and OUT/summary.csv (columns id, scene, overrides, status, exit_code,
/// signal, seconds, job_seconds, coarse_triangles, refined_triangles, message), each atomically.
/// \pre result.jobs.size() == manifest.jobs.size(). \throw RunError when they cannot be written.
void write_batch_summary(const Manifest& manifest, const BatchResult& result, const std::filesystem::path& out);

/// The folder of job `id`: OUT/jobs/<id>.
std::filesystem::path job_folder(const std::filesystem::path& out, const std::string& id);

}  // namespace fracref
