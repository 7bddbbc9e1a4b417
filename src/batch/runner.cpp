// The process pool: posix_spawn one child per job, poll them, record how each ended.
#include "batch/runner.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <fstream>
#include <set>
#include <thread>

#include "batch/batch_internal.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

extern char** environ;

namespace fracref {
namespace fs = std::filesystem;
using namespace batch_detail;
namespace {

using Clock = std::chrono::steady_clock;

struct Running {
  pid_t pid = 0;
  std::size_t index = 0;
  Clock::time_point start;
};

/// Starts `args` with stdin from /dev/null and stdout and stderr appended to `log`.
/// \throw RunError when the process cannot be started.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int err = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) throw RunError("cannot start " + args[0] + ": " + std::strerror(err));
  return pid;
}

void append(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::app);
  out << text;
  if (!out) throw RunError(file.string() + ": cannot write");
}

/// Prepares and starts one job; a job that cannot even start is recorded as failed at once.
/// \return the running child, or nullopt when the job ended before starting.
std::optional<Running> start_job(const BatchJob& job, std::size_t index, const BatchRunOptions& o, DemoScenes& demos,
                                 JobOutcome& outcome) {
  const fs::path folder = job_folder(o.out, job.id);
  fs::create_directories(folder);
  fs::remove(folder / "status.json");
  write_file_atomic(folder / "job.json", job_spec(job, o).dump(2) + "\n");
  const fs::path log = folder / "log.txt";
  std::ofstream(log, std::ios::binary | std::ios::trunc).close();
  try {
    std::vector<std::string> args = job_command(job, o, folder, demos);
    append(log, "$ " + shell_line(args) + "\n");
    // Timed from before the spawn: on a loaded machine the parent may resume only after a short
    // child has already exited.
    const Clock::time_point start = Clock::now();
    return Running{spawn(args, log), index, start};
  } catch (const InputError& e) {
    outcome.exit_code = kExitBadInput;
    outcome.message = std::string("fracref: batch: ") + e.what();
  } catch (const std::exception& e) {
    outcome.exit_code = kExitFailure;
    outcome.message = std::string("fracref: batch: ") + e.what();
  }
  append(log, outcome.message + "\n");
  outcome.status = JobStatus::failed;
  write_status(folder, outcome);
  return std::nullopt;
}

/// Records how a child ended (`status` from waitpid).
void finish_job(const BatchJob& job, const Running& r, int status, const BatchRunOptions& o, JobOutcome& outcome) {
  const fs::path folder = job_folder(o.out, job.id);
  outcome.seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
  read_report(folder, outcome);
  if (WIFSIGNALED(status)) {
    outcome.status = JobStatus::crashed;
    outcome.signal = WTERMSIG(status);
    outcome.message = "killed by signal " + std::to_string(outcome.signal) + " (" + strsignal(outcome.signal) + ")";
    const std::string last = last_log_line(folder / "log.txt");
    if (!last.empty() && last[0] != '$') outcome.message += "; last output: " + last;
    append(folder / "log.txt", "fracref: batch: " + outcome.message + "\n");
  } else {
    outcome.exit_code = WEXITSTATUS(status);
    const bool complete = outcome.job_seconds.has_value();
    outcome.status = *outcome.exit_code == 0 && complete ? JobStatus::ok : JobStatus::failed;
    if (*outcome.exit_code != 0) outcome.message = last_log_line(folder / "log.txt");
    else if (!complete) outcome.message = "exited with 0 but wrote no complete output/report.json";
  }
  write_status(folder, outcome);
}

void count(BatchProgress& p, JobStatus s) {
  ++p.done;
  if (s == JobStatus::ok) ++p.ok;
  else if (s == JobStatus::failed) ++p.failed;
  else if (s == JobStatus::crashed) ++p.crashed;
  else if (s == JobStatus::skipped) ++p.skipped;
}

/// Polls the children; returns those that ended with their waitpid status.
std::vector<std::pair<Running, int>> reap(std::vector<Running>& running) {
  std::vector<std::pair<Running, int>> ended;
  for (auto it = running.begin(); it != running.end();) {
    int status = 0;
    pid_t got = ::waitpid(it->pid, &status, WNOHANG);
    while (got < 0 && errno == EINTR) got = ::waitpid(it->pid, &status, WNOHANG);
    if (got == it->pid || got < 0) {
      ended.push_back({*it, got < 0 ? (128 << 8) : status});  // lost child: exit code 128
      it = running.erase(it);
    } else {
      ++it;
    }
  }
  return ended;
}

}  // namespace

const char* to_string(JobStatus status) {
  switch (status) {
    case JobStatus::ok: return "ok";
    case JobStatus::failed: return "failed";
    case JobStatus::crashed: return "crashed";
    case JobStatus::skipped: return "skipped";
    case JobStatus::pending: return "pending";
  }
  return "?";
}

std::size_t BatchResult::count(JobStatus status) const {
  return std::size_t(std::count_if(jobs.begin(), jobs.end(), [&](const JobOutcome& o) { return o.status == status; }));
}

bool BatchResult::success() const { return count(JobStatus::failed) == 0 && count(JobStatus::crashed) == 0; }

fs::path job_folder(const fs::path& out, const std::string& id) { return out / "jobs" / id; }

BatchResult run_batch(const Manifest& manifest, const BatchRunOptions& o) {
  if (o.parallel < 1) throw InputError("batch: -j must be at least 1, got " + std::to_string(o.parallel));
  std::set<std::string> only(o.only.begin(), o.only.end());
  for (const std::string& id : only)
    if (std::none_of(manifest.jobs.begin(), manifest.jobs.end(), [&](const BatchJob& j) { return j.id == id; }))
      throw InputError(manifest.file.string() + ": no job has the id '" + id + "' (fracref batch --list shows them)");
  fs::create_directories(o.out / "jobs");
  BatchResult result;
  result.jobs.resize(manifest.jobs.size());
  BatchProgress progress;
  std::deque<std::size_t> queue;
  for (std::size_t i = 0; i < manifest.jobs.size(); ++i) {
    const BatchJob& job = manifest.jobs[i];
    const fs::path folder = job_folder(o.out, job.id);
    const bool complete = is_complete(folder, job_spec(job, o));
    const bool selected = !o.summary_only && (only.empty() || only.count(job.id));
    if (selected && !complete) queue.push_back(i);
    else result.jobs[i] = recorded_outcome(folder, complete);
    if (selected) ++progress.total;
    if (selected && complete) count(progress, JobStatus::skipped);
  }
  auto report = [&] {
    if (o.progress) o.progress(progress);
  };
  report();
  DemoScenes demos;
  std::vector<Running> running;
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && int(running.size()) < o.parallel) {
      const std::size_t i = queue.front();
      queue.pop_front();
      if (auto r = start_job(manifest.jobs[i], i, o, demos, result.jobs[i])) running.push_back(*r);
      else count(progress, result.jobs[i].status);
      progress.running = running.size();
      report();
    }
    std::vector<std::pair<Running, int>> ended = reap(running);
    for (const auto& [r, status] : ended) {
      finish_job(manifest.jobs[r.index], r, status, o, result.jobs[r.index]);
      count(progress, result.jobs[r.index].status);
    }
    progress.running = running.size();
    if (!ended.empty()) report();
    else if (!running.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return result;
}

}  // namespace fracref
