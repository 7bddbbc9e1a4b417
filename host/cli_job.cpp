#include "cli_job.hpp"
#include "cli.hpp"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "io/mesh_io.hpp"
#include "io/mesh_stats.hpp"
#include "preview/raster.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"
#include "version.hpp"
#include "cli_backend.hpp"
#include "cli_progress.hpp"
#include "pipeline/job.hpp"
#include "scene/scene.hpp"

namespace fracref::cli {
namespace fs = std::filesystem;
namespace {

const std::vector<std::string> kDemoScenes = {"bunny", "branch", "wall", "clay", "jello"};

fs::path executable_dir() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::current_path() : exe.parent_path();
}

/// Where set-up put the data the demos need (the npm bunny): FRACREF_DATA_DIR or <exe>/data.
fs::path data_dir() {
  if (const char* env = std::getenv("FRACREF_DATA_DIR")) return env;
  return executable_dir() / "data";
}

PreviewMesh exterior_preview(const MeshSoup& soup) {
  PreviewMesh m;
  m.positions = soup.positions;
  m.triangles = soup.triangles;
  m.triangle_colors.assign(soup.triangles.size(), glm::vec3(0.78f, 0.80f, 0.86f));
  return m;
}

int run_exterior_only(const std::string& name, const fs::path& exterior, const JobCliOptions& o) {
  MeshSoup soup = read_mesh(exterior);
  MeshStats stats = mesh_stats(soup);
  if (!stats.closed)
    throw InputError(exterior.string() + ": the exterior surface is not closed (" +
                     std::to_string(stats.boundary_edges) + " boundary edges, " +
                     std::to_string(stats.non_manifold_edges) + " non-manifold edges)");
  StagedDirectory out(o.output);
  write_mesh(out.path() / "exterior.ply", soup);
  write_png(out.path() / "preview.png", render_preview({exterior_preview(soup)}));
  nlohmann::ordered_json report;
  report["version"] = kVersion;
  report["scene"] = name;
  report["exterior"] = {{"file", exterior.string()}, {"vertices", stats.vertices}, {"faces", stats.faces}};
  report["stages_run"] = {"load"};
  write_file_atomic(out.path() / "report.json", report.dump(2) + "\n");
  out.commit();
  std::cerr << "fracref: loaded the exterior of '" << name << "' (" << stats.faces
            << " triangles) into " << o.output << "; the refiner is not implemented yet\n";
  return kExitOk;
}

}  // namespace

/// Runs one scene into o.output through a staged folder, with a progress line on a terminal.
static int run_scene(const Scene& scene, const JobCliOptions& o, const fs::path* extra_input) {
  JobOptions jo;
  jo.stop_after = parse_stage(o.stop_after);
  jo.seed = o.seed;
  if (o.preview_frames > 0) jo.preview_frames = o.preview_frames;
  std::unique_ptr<ComputeBackend> backend = make_backend(o.backend, o.quiet);
  StagedDirectory out(o.output);
  if (extra_input) fs::rename(*extra_input, out.path() / "input");
  ProgressLine line(!o.quiet && stderr_is_terminal());
  jo.progress = [&](const std::string& stage, double f, const std::string& d) { line.update(stage, f, d); };
  nlohmann::ordered_json report = run_job(scene, out.path(), *backend, jo);
  line.done();
  out.commit();
  if (!o.quiet) {
    std::cerr << "fracref: " << scene.name << ": ";
    if (report.contains("refined_triangles"))
      std::cerr << report["coarse_triangles"] << " -> " << report["refined_triangles"] << " triangles, ";
    std::cerr << report["seconds"]["total"].get<double>() << " s; output in " << o.output << "\n";
  }
  return kExitOk;
}

int run_refine(const JobCliOptions& o) {
  Scene scene = load_scene(o.scene);
  return run_scene(scene, o, nullptr);
}

int run_demo(const JobCliOptions& o) {
  if (o.list) {
    for (const auto& n : kDemoScenes) std::cout << n << "\n";
    return kExitOk;
  }
  if (o.scene.empty()) throw InputError("demo: a scene name is required (fracref demo --list shows them)");
  if (std::find(kDemoScenes.begin(), kDemoScenes.end(), o.scene) == kDemoScenes.end())
    throw InputError("demo: unknown scene '" + o.scene + "' (available: bunny, branch, wall, clay, jello)");
  if (o.output.empty()) throw InputError("demo: -o/--output is required");
  if (o.scene != "bunny") {
    std::cerr << "fracref: demo '" << o.scene << "' is not implemented yet in this version\n";
    return kExitFailure;
  }
  fs::path bunny = data_dir() / "bunny.obj";
  if (!fs::exists(bunny))
    throw InputError(bunny.string() + ": the bunny is missing; run 'bash .ci/setup build' (it fetches npm bunny@1.0.1)");
  return run_exterior_only(o.scene, bunny, o);
}

}  // namespace fracref::cli
