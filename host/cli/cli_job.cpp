#include "cli_job.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "cli_backend.hpp"
#include "cli_progress.hpp"
#include "batch/manifest.hpp"
#include "pipeline/job.hpp"
#include "scene/json_strict.hpp"
#include "scene/scene.hpp"
#include "scenegen/scenegen.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref::cli {
namespace fs = std::filesystem;
namespace {

/// Runs one scene into o.output through a staged folder, with a progress line on a terminal;
/// `extra_input` (the generated inputs of a demo) is moved to OUT/input when the run succeeds.
int run_scene(const Scene& scene, const JobCliOptions& o, const fs::path* extra_input) {
  JobOptions jo;
  jo.stop_after = parse_stage(o.stop_after);
  jo.seed = o.seed;
  if (o.preview_frames > 0) jo.preview_frames = o.preview_frames;
  std::string backend_note;
  std::unique_ptr<ComputeBackend> backend = make_backend(o.backend, backend_note);
  StagedDirectory out(o.output);
  ProgressLine line(!o.quiet && stderr_is_terminal());
  std::string current_stage;
  jo.progress = [&](const std::string& stage, double f, const std::string& d) {
    if (stage != current_stage) set_activity("running the " + (current_stage = stage) + " stage");
    line.update(stage, f, d);
  };
  nlohmann::ordered_json report = run_job(scene, out.path(), *backend, jo);
  line.done();
  if (extra_input) fs::rename(*extra_input, out.path() / "input");
  set_activity("writing " + o.output);
  out.commit();
  if (!o.quiet) {
    if (!backend_note.empty()) std::cerr << "fracref: " << backend_note << "\n";
    std::cerr << "fracref: " << scene.name << ": ";
    if (report.contains("refined_triangles"))
      std::cerr << report["coarse_triangles"] << " -> " << report["refined_triangles"] << " triangles, ";
    std::cerr << report["seconds"]["total"].get<double>() << " s; output in " << o.output << "\n";
  }
  return kExitOk;
}

// The scene file with the --set overrides applied (values read as JSON, else as strings).
nlohmann::json overridden(const fs::path& file, const std::vector<std::string>& sets) {
  std::vector<SceneOverride> overrides;
  for (const std::string& set : sets) {
    const std::size_t eq = set.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set '" + set + "': expected KEY=VALUE, e.g. refine.tau=0.001");
    nlohmann::json value = nlohmann::json::parse(set.substr(eq + 1), nullptr, false);
    if (value.is_discarded()) value = set.substr(eq + 1);
    overrides.emplace_back(set.substr(0, eq), value);
  }
  nlohmann::json scene = read_json_file(file);
  apply_overrides(scene, overrides, "--set");
  return scene;
}

// A scene file, with the --set overrides; for a demo (`rewrite`) they are written into its
// generated file, so that OUT/input repeats the run.
Scene load_with_overrides(const fs::path& file, const std::vector<std::string>& sets, bool rewrite) {
  if (sets.empty()) return load_scene(file);
  const nlohmann::json scene = overridden(file, sets);
  Scene out;
  try {
    out = parse_scene(scene, file);
  } catch (const InputError& e) {
    // A demo's file is a temporary one: name the scene by what the user typed.
    std::string what = e.what();
    if (rewrite && what.rfind(file.string(), 0) == 0) what = "demo " + file.stem().string() + what.substr(file.string().size());
    throw InputError(what + " (after --set)");
  }
  if (rewrite) std::ofstream(file, std::ios::binary | std::ios::trunc) << scene.dump(2) << "\n";
  return out;
}

}  // namespace

int run_refine(const JobCliOptions& o) {
  set_activity("reading the scene file " + o.scene);
  Scene scene = load_with_overrides(o.scene, o.sets, false);
  return run_scene(scene, o, nullptr);
}

int run_demo(const JobCliOptions& o) {
  if (o.list) {
    for (const auto& n : demo_scene_names()) std::cout << n << "\n";
    return kExitOk;
  }
  if (o.scene.empty()) throw InputError("demo: a scene name is required (fracref demo --list shows them)");
  const std::vector<std::string> names = demo_scene_names();
  if (std::find(names.begin(), names.end(), o.scene) == names.end())
    throw InputError("demo: unknown scene '" + o.scene + "' (available: bunny, branch, wall, clay, jello)");
  if (o.output.empty()) throw InputError("demo: -o/--output is required");
  DemoOptions demo;
  demo.bunny_obj = data_dir() / "bunny.obj";
  if (o.scene == "bunny" && !fs::exists(demo.bunny_obj))
    throw InputError(demo.bunny_obj.string() +
                     ": the bunny is missing; run 'bash .ci/setup build' (it fetches npm bunny@1.0.1)");
  // The generated inputs are real files in the user formats; they travel with the output
  // (OUT/input/) so the run can be repeated with `fracref refine OUT/input/NAME.json`.
  check_output_target(o.output);  // before anything is generated beside it
  remove_stale_staging(o.output);
  fs::path input = fs::path(o.output).parent_path() /
                   (fs::path(o.output).filename().string() + ".input-tmp-" + std::to_string(::getpid()));
  fs::remove_all(input);
  struct Cleanup {
    fs::path p;
    int slot = register_for_cleanup(p);
    ~Cleanup() {
      unregister_for_cleanup(slot);
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } cleanup{input};
  fs::path scene_file = generate_demo_scene(o.scene, input, demo);
  Scene scene = load_with_overrides(scene_file, o.sets, true);
  return run_scene(scene, o, &input);
}

}  // namespace fracref::cli
