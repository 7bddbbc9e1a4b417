// `fracref batch MANIFEST`: many jobs from a manifest, each a child process of this binary
// (scenes/BATCH.md), with a summary at the end.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>

#include "batch/runner.hpp"
#include "util/parallel.hpp"
#include "cli.hpp"
#include "cli_progress.hpp"
#include "scenegen/scenegen.hpp"
#include "util/error.hpp"

namespace fracref::cli {
namespace fs = std::filesystem;
namespace {

struct BatchCliOptions {
  std::string manifest;
  std::string output;
  int parallel = 1;
  int threads = 0;
  std::string backend = "auto";
  std::string stop_after;
  std::vector<std::string> only;
  std::optional<std::size_t> index;
  bool list = false;
  bool summary_only = false;
  bool quiet = false;
};

fs::path self_executable() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw RunError("batch: cannot find this program's path (/proc/self/exe): " + ec.message());
  return exe;
}

/// The default output folder: beside the manifest, its name without .json plus ".out".
fs::path default_output(const fs::path& manifest) {
  return manifest.parent_path() / (manifest.stem().string() + ".out");
}

void print_summary(const BatchResult& r, const Manifest& m, const fs::path& out) {
  std::cerr << "fracref: batch: " << r.count(JobStatus::ok) << " ok, " << r.count(JobStatus::failed) << " failed, "
            << r.count(JobStatus::crashed) << " crashed, " << r.count(JobStatus::skipped) << " skipped";
  if (std::size_t p = r.count(JobStatus::pending)) std::cerr << ", " << p << " pending";
  std::cerr << "; summary in " << (out / "summary.csv").string() << "\n";
  for (std::size_t i = 0; i < m.jobs.size(); ++i)
    if (r.jobs[i].status == JobStatus::failed || r.jobs[i].status == JobStatus::crashed)
      std::cerr << "  " << m.jobs[i].id << ": " << to_string(r.jobs[i].status) << ": " << r.jobs[i].message
                << " (log: " << (job_folder(out, m.jobs[i].id) / "log.txt").string() << ")\n";
}

int run_batch_command(const BatchCliOptions& c) {
  const Manifest m = load_manifest(c.manifest, demo_scene_names());
  if (c.list) {
    for (const BatchJob& j : m.jobs) std::cout << j.id << "\n";
    return kExitOk;
  }
  BatchRunOptions o;
  o.exe = self_executable();
  o.out = c.output.empty() ? default_output(m.file) : fs::absolute(c.output).lexically_normal();
  o.parallel = c.parallel;
  // Jobs side by side share the machine's threads rather than each taking all of them.
  o.threads = c.threads > 0 ? c.threads : std::max(1, default_threads() / std::max(1, c.parallel));
  o.backend = c.backend;
  o.stop_after = c.stop_after;
  o.only = c.only;
  o.summary_only = c.summary_only;
  if (c.index) {
    if (*c.index >= m.jobs.size())
      throw InputError("batch: --index " + std::to_string(*c.index) + " is past the last job (the manifest has " +
                       std::to_string(m.jobs.size()) + ", numbered from 0)");
    o.only.push_back(m.jobs[*c.index].id);
  }
  o.generate_demo = [](const std::string& name, const fs::path& folder) {
    DemoOptions demo;
    demo.bunny_obj = data_dir() / "bunny.obj";
    return generate_demo_scene(name, folder, demo);
  };
  ProgressLine line(!c.quiet && stderr_is_terminal());
  o.progress = [&](const BatchProgress& p) {
    const double f = p.total ? double(p.done) / double(p.total) : 1.0;
    line.update("batch", f,
                std::to_string(p.done) + "/" + std::to_string(p.total) + " done: " + std::to_string(p.ok) + " ok, " +
                    std::to_string(p.failed) + " failed, " + std::to_string(p.crashed) + " crashed, " +
                    std::to_string(p.skipped) + " skipped; " + std::to_string(p.running) + " running");
  };
  const BatchResult r = run_batch(m, o);
  line.done();
  write_batch_summary(m, r, o.out);
  if (!c.quiet || !r.success()) print_summary(r, m, o.out);
  return r.success() ? kExitOk : kExitFailure;
}

}  // namespace

void add_batch_command(CLI::App& app, Action& action) {
  auto c = std::make_shared<BatchCliOptions>();
  CLI::App* sub = app.add_subcommand("batch", "Run many refinement jobs from a manifest (resumable)");
  sub->footer("Manifest format, resuming and spreading a batch over machines: scenes/BATCH.md.\n"
              "Exit code 1 when any job failed or crashed (the others still run), 2 for a bad manifest.");
  sub->add_option("manifest", c->manifest, "manifest file (JSON)")->required();
  sub->add_option("-o,--output", c->output, "output folder (default: MANIFEST without .json, plus .out)");
  sub->add_option("-j,--jobs", c->parallel, "run at most N jobs at once (default 1)")->check(CLI::PositiveNumber);
  sub->add_option("--threads", c->threads, "worker threads of each job (default: the machine's hardware threads / --jobs)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--backend", c->backend, "backend of the jobs that name none: cpu, vulkan or auto")
      ->check(CLI::IsMember({"cpu", "vulkan", "auto"}));
  sub->add_option("--stop-after", c->stop_after, "last stage of the jobs that name none")
      ->check(CLI::IsMember({"preprocess", "refine", "pieces", "animate"}));
  sub->add_option("--only", c->only, "run only these job ids (comma separated)")->delimiter(',');
  sub->add_option("--index", c->index, "run only the job at this position of --list, from 0 (e.g. a Slurm array task id)");
  sub->add_flag("--list", c->list, "print the job ids, one a line, and exit");
  sub->add_flag("--summary-only", c->summary_only, "run nothing; write the summary from the job folders");
  sub->add_flag("-q,--quiet", c->quiet, "no progress line and no summary line unless a job failed");
  sub->callback([c, &action] { action = [c] { return run_batch_command(*c); }; });
}

}  // namespace fracref::cli
