// `fracref refine SCENE` and `fracref demo NAME`: one job each, written into a staged folder.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli.hpp"
#include "cli_job.hpp"
#include "util/error.hpp"

namespace fracref::cli {
namespace {

void add_job_options(CLI::App* sub, JobCliOptions& o) {
  sub->add_option("-o,--output", o.output, "output folder (replaced only when the run completes)")->required();
  sub->add_option("--backend", o.backend, "compute backend: cpu, vulkan or auto")
      ->check(CLI::IsMember({"cpu", "vulkan", "auto"}));
  sub->add_option("--seed", o.seed, "random seed (overrides the scene's refine.seed)");
  sub->add_option("--stop-after", o.stop_after, "last stage to run: preprocess, refine, pieces, animate")
      ->check(CLI::IsMember({"preprocess", "refine", "pieces", "animate"}));
  sub->add_option("--preview-frames", o.preview_frames, "also render a contact sheet of N animation frames");
  sub->add_option("--set", o.sets, "override a scene key, e.g. --set refine.tau=0.001 (repeatable)");
  sub->add_flag("-q,--quiet", o.quiet, "no progress line");
  add_threads_option(sub);
}

}  // namespace

void add_refine_commands(CLI::App& app, Action& action) {
  auto refine = std::make_shared<JobCliOptions>();
  CLI::App* r = app.add_subcommand("refine", "Refine the coarse fracture described by a scene file (JSON)");
  r->add_option("scene", refine->scene, "scene file (schema: README, 'Scene files')")->required();
  add_job_options(r, *refine);
  r->callback([refine, &action] { action = [refine] { return run_refine(*refine); }; });

  auto demo = std::make_shared<JobCliOptions>();
  CLI::App* d = app.add_subcommand("demo", "Run one of the paper's scenes: bunny, branch, wall, clay, jello");
  d->add_option("name", demo->scene, "scene name (see --list)");
  d->add_flag("--list", demo->list, "list the built-in scenes and exit");
  add_job_options(d, *demo);
  d->get_option("--output")->required(false);
  d->callback([demo, &action] { action = [demo] { return run_demo(*demo); }; });
}

}  // namespace fracref::cli
