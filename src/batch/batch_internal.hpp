#pragma once
// Internals of the batch runner shared by its .cpp files.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/runner.hpp"

namespace fracref::batch_detail {

/// What identifies a job's result: a complete output is reused only when this matches.
nlohmann::json job_spec(const BatchJob& job, const BatchRunOptions& options);

/// The folder holds output/report.json with seconds.total and a job.json equal to `spec`.
bool is_complete(const std::filesystem::path& folder, const nlohmann::json& spec);

/// Scene files of demos generated for overrides, by name (one generation per batch run).
using DemoScenes = std::map<std::string, std::filesystem::path>;

/// The command line (argv[0] = options.exe) that runs `job` into folder/output. Writes
/// folder/scene.json for jobs with scene overrides.
/// \throw InputError when the scene cannot be read or an override does not fit it (the message
///        names the scene file and the key), RunError when a file cannot be written.
std::vector<std::string> job_command(const BatchJob& job, const BatchRunOptions& options,
                                     const std::filesystem::path& folder, DemoScenes& demos);

/// Fills the report's counts into `outcome` (nothing when output/report.json is missing or bad).
void read_report(const std::filesystem::path& folder, JobOutcome& outcome);

/// The outcome recorded by an earlier run: skipped when `complete`, else status.json's, else
/// pending.
JobOutcome recorded_outcome(const std::filesystem::path& folder, bool complete);

/// Writes folder/status.json for `outcome`.
void write_status(const std::filesystem::path& folder, const JobOutcome& outcome);

/// The last non-empty line of a log file, at most 300 characters ("" when none).
std::string last_log_line(const std::filesystem::path& log);

/// `args` as a shell would read them (single quotes where needed).
std::string shell_line(const std::vector<std::string>& args);

}  // namespace fracref::batch_detail
