#include "pipeline/job.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "coarse/animation.hpp"
#include "coarse/coarse_model.hpp"
#include "coarse/cuts_model.hpp"
#include "coarse/pieces_fit.hpp"
#include "field/field_sampler.hpp"
#include "field/grid_file.hpp"
#include "field/procedural.hpp"
#include "field/strength.hpp"
#include "flow/timed_backend.hpp"
#include "io/mesh_io.hpp"
#include "pipeline/job_outputs.hpp"
#include "pipeline/surface_preview.hpp"
#include "pipeline/material.hpp"
#include "pipeline/section_preview.hpp"
#include "animate/animate.hpp"
#include "animate/gltf_writer.hpp"
#include "animate/piece_surface.hpp"
#include "pieces/pieces.hpp"
#include "refine/refine.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"
#include "version.hpp"

namespace fracref {
namespace fs = std::filesystem;

Stage parse_stage(const std::string& name) {
  for (Stage s : {Stage::preprocess, Stage::refine, Stage::pieces, Stage::animate})
    if (name == to_string(s)) return s;
  throw InputError("--stop-after: unknown stage '" + name + "' (preprocess, refine, pieces, animate)");
}

const char* to_string(Stage stage) {
  switch (stage) {
    case Stage::preprocess: return "preprocess";
    case Stage::refine: return "refine";
    case Stage::pieces: return "pieces";
    case Stage::animate: return "animate";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Pieces that conform exactly keep their own faces; others are fitted on a lattice of the
// exterior (coarse/pieces_fit.hpp), which gives the model vertices of its own: per-frame positions
// of the pieces' vertices no longer apply.
CoarseModel load_pieces_scene(const Scene& scene) {
  const FractureSpec& f = scene.fracture;
  FitOptions o;
  o.tolerance = f.tolerance;
  if (f.cells_per_diagonal > 0.0) o.cells_per_diagonal = f.cells_per_diagonal;  // 0: automatic, FitOptions' default
  o.own_vertices = scene.animation.kind == AnimationKind::rigid;
  const std::vector<PieceInput> pieces = f.files.empty() ? read_pieces(f.mesh) : read_pieces(f.files);
  CoarseModel m = build_pieces_or_fit(read_mesh(scene.exterior), scene.exterior.string(), pieces, {}, o);
  if (m.fit.fitted && scene.animation.kind == AnimationKind::frames)
    throw InputError(scene.file.string() + ": key 'animation.kind': 'frames' needs pieces that conform exactly (the " +
                     "frames move the pieces' own vertices), but these were fitted to the exterior because " + m.fit.reason +
                     "; animate them with kind 'rigid' (one transform per piece)");
  return m;
}

CoarseModel load_coarse(const Scene& scene) {
  const FractureSpec& f = scene.fracture;
  switch (f.kind) {
    case FractureKind::tets: {
      TetModelOptions o;
      o.virtual_fracture = f.virtual_fracture;
      o.own_vertices = scene.animation.kind == AnimationKind::rigid;
      return load_tet_model(f.mesh, f.cracks, o);
    }
    case FractureKind::pieces: return load_pieces_scene(scene);
    case FractureKind::cuts: {
      CutsOptions o;
      o.virtual_fracture = f.virtual_fracture;
      o.cells_per_diagonal = f.cells_per_diagonal;
      return load_cuts_model(scene.exterior, f.mesh, o);
    }
  }
  throw InputError(scene.file.string() + ": key 'fracture.kind': unknown kind");
}

CoarseAnimation load_animation(const Scene& scene, const CoarseModel& model) {
  const AnimationSpec& a = scene.animation;
  if (a.kind == AnimationKind::frames) return load_frames(a.frames, a.first, a.count, a.fps, a.parent_map, model);
  if (a.kind == AnimationKind::rigid) return load_rigid(a.transforms, a.fps, model);
  return {};
}

struct Field {
  Grid3 zeta;
  FieldGrid4 sampled;
  std::optional<FieldSpec> material;  // a procedural field's; its colours are the preview's
};

Field build_field(const Scene& scene, const ExteriorSurface& b, const CoarseModel& model, ComputeBackend& backend) {
  const double diag = b.diagonal();
  const glm::dvec3 pad(scene.field.padding * diag);
  Field f;
  if (scene.field.type == FieldType::grid) {
    f.zeta = load_strength_grid(scene.field.file, b.bbox_min, b.bbox_max, scene.field.resolution);  // the file's own box and resolution
  } else {
    FieldSpec material = material_from_scene(scene.field, scene.file, b.bbox_min, b.bbox_max);
    f.zeta = sample_strength(material, b.bbox_min - pad, b.bbox_max + pad, scene.field.resolution);
    f.material = material;
  }
  std::vector<glm::dvec3> pos;
  for (const glm::vec4& p : model.surface.positions) pos.push_back(glm::dvec3(glm::vec3(p)));
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const glm::uvec4& t : model.surface.faces) tris.push_back({t.x, t.y, t.z});
  const FieldWeights weights{scene.weights.strength, scene.weights.distance, scene.weights.offset};
  Grid3 psi = modified_field(f.zeta, distance_grid(f.zeta, pos, tris), weights, diag);
  PyramidOptions po;
  po.levels = scene.pyramid.levels;
  po.sigma = float(scene.pyramid.sigma);
  f.sampled = precompute_field_gradient(backend.build_pyramid(psi, po));
  return f;
}

// The material's own colours, where it has some, for preview.png and animation.glb: sampled
// when the pieces are drawn or written (so the set-up's time is the refinement's alone), over
// ζ's box, up to four times finer than ζ's grid per axis (at ζ's own spacing a marble vein's edge
// shows the grid's cells as steps) and within kColourNodes nodes (48 MB), coarser than ζ's grid
// where that is larger: a 1600×1000 picture shows no more. None for the other materials (ζ's
// ramp colours them).
std::optional<std::array<Grid3, 3>> material_colours(const Field& field) {
  constexpr double kColourNodes = 4e6;
  if (!field.material) return std::nullopt;
  const glm::uvec3 n = field.zeta.dims;
  const double nodes = double(n.x) * double(n.y) * double(n.z);
  const double f = std::min(4.0, std::cbrt(kColourNodes / nodes));  // colour nodes per ζ cell and axis
  Grid3 colours;
  colours.origin = field.zeta.origin, colours.cell = field.zeta.cell / f;
  for (int a = 0; a < 3; ++a) colours.dims[a] = unsigned(std::floor(double(n[a] - 1) * f + 1e-9)) + 1u;
  return sample_albedo(*field.material, colours);
}

RefineOptions refine_options(const Scene& scene, const JobOptions& o, const CoarseModel& model, double diag) {
  RefineOptions r;
  r.scale = diag;
  r.tau = scene.refine.tau;
  r.delta = scene.refine.delta;
  r.step = scene.refine.step;
  r.tolerance = scene.refine.tolerance;
  r.max_iterations = scene.refine.max_iterations;
  r.rim_motion = scene.refine.rim_motion;
  r.tangential_motion = scene.refine.tangential_motion;
  r.relax = scene.refine.relax;
  const bool lattice = scene.fracture.kind == FractureKind::cuts || model.fit.fitted;
  r.rim_smoothing = scene.refine.rim_smoothing.value_or(lattice ? kLatticeRimSmoothing : 0);
  r.fold_solves = scene.refine.fold_solves;
  r.hairpin_collapse = scene.refine.hairpin_collapse;
  r.max_triangles = std::size_t(scene.refine.max_triangles);
  r.seed = o.seed.value_or(scene.refine.seed);
  r.min_angle = scene.refine.min_angle;
  r.collisions = scene.refine.collisions;
  return r;
}

// The field's grids take about this many bytes a node: ζ, the distance, ψ and the pyramid's levels
// (4 bytes each, the pyramid ~1.15 times the base), the (ψ, ∇ψ) grid (16), and the copies a
// backend keeps (the Vulkan one uploads the pyramid and the field).
constexpr double kFieldBytesPerNode = 64.0;

// Refuses, before anything is read, a field resolution whose grids would not fit in this machine's
// memory (it ended in a bare std::bad_alloc after minutes).
void check_field_memory(const Scene& scene) {
  const glm::uvec3 r = scene.field.resolution;
  const double bytes = kFieldBytesPerNode * double(r.x) * double(r.y) * double(r.z);
  const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
  if (!(memory > 0.0) || bytes <= 0.8 * memory) return;
  auto gb = [](double b) {
    std::ostringstream s;
    s.precision(3);
    s << b / 1e9 << " GB";
    return s.str();
  };
  throw InputError(scene.file.string() + ": key 'field.resolution': [" + std::to_string(r.x) + ", " + std::to_string(r.y) +
                   ", " + std::to_string(r.z) + "] needs about " + gb(bytes) + " for the field, more than this machine's " +
                   gb(memory) + " of memory allows: lower the resolution");
}

}  // namespace

nlohmann::ordered_json run_job(const Scene& scene, const fs::path& out, ComputeBackend& inner, const JobOptions& o) {
  check_field_memory(scene);
  const auto t0 = Clock::now();
  TimedBackend backend(inner);  // the kernels' share of set-up and refine, for the report
  auto progress = [&](const std::string& stage, double f, const std::string& d) {
    if (o.progress) o.progress(stage, f, d);
  };
  JobReport report(scene, backend.name(), o.seed.value_or(scene.refine.seed));
  progress("load", 0.0, scene.exterior.filename().string());
  // The exterior and the coarse model with its animation are independent: read side by side
  // (an error of the exterior still comes first, as when read in turn).
  MeshSoup exterior_mesh;
  ExteriorSurface b;
  CoarseModel model;
  CoarseAnimation animation;
  parallel_pair(
      [&] {
        exterior_mesh = read_mesh(scene.exterior);
        b = make_exterior(exterior_mesh, scene.exterior.string());
      },
      [&] {
        model = load_coarse(scene);
        animation = load_animation(scene, model);
      });
  if (model.surface.faces.empty()) {
    const std::filesystem::path what = !scene.fracture.mesh.empty() ? scene.fracture.mesh
                                       : !scene.fracture.files.empty() ? scene.fracture.files.front() : scene.file;
    throw InputError(what.string() + ": the fracture has " + std::to_string(model.piece_count) +
                     " piece(s) and no fracture surface between them: there is nothing to refine (label the tetrahedra or "
                     "group the pieces so that at least two pieces meet)");
  }
  report.coarse(model, animation);
  write_surface_ply(out / "coarse_surface.ply", model.surface, nullptr);
  if (o.stop_after == Stage::preprocess) {
    report.seconds("setup", seconds_since(t0));
    return report.finish(out, seconds_since(t0), [&] { return preview_surface(model.surface, exterior_mesh); });
  }
  progress("field", 0.0, "strength field and pyramid");
  Field field = build_field(scene, b, model, backend);
  report.seconds("setup", seconds_since(t0));
  const auto t_refine = Clock::now();
  FractureSurface s = model.surface;
  RefineOptions ro = refine_options(scene, o, model, b.diagonal());
  report.rim_smoothing(ro.rim_smoothing);
  RefineResult refined = refine_surface(s, field.sampled, b, backend, ro, [&](const IterationStats& st, int it, int max) {
    progress("refine", double(it + 1) / max, std::to_string(st.triangles) + " triangles");
  });
  report.seconds("refine", seconds_since(t_refine));
  report.kernels(backend.seconds());
  report.refined(model.surface, s, refined, field.zeta, b.diagonal());
  const SurfaceQuality quality = measure_quality(model.surface, s, field.sampled, field.zeta, b);
  report.quality(quality);
  write_surface_ply(out / "fracture_surface.ply", s, &refined.tree, &field.zeta);
  if (scene.output.preview) {
    write_png(out / "preview_surface.png", preview_strength_surface(s, field.zeta));
    write_png(out / "preview_section.png",
              preview_section(field.zeta, quality.weak_threshold, exterior_mesh, model.surface, s));
  }
  write_mesh(out / "exterior.ply", exterior_mesh);
  if (o.stop_after == Stage::refine)
    return report.finish(out, seconds_since(t0), [&] { return preview_surface(s, exterior_mesh); });
  progress("pieces", 0.0, "cutting the exterior");
  const auto t_pieces = Clock::now();
  PieceSet pieces = build_pieces(s, b.mesh, refined.rim);
  PieceReport checked = check_pieces(pieces, exterior_mesh);
  report.pieces(pieces, checked);
  require_valid_pieces(checked);
  if (scene.output.ply) write_pieces(pieces, out);
  if (scene.output.obj) write_piece_objs(pieces, out);
  report.seconds("pieces", seconds_since(t_pieces));
  if (o.stop_after == Stage::pieces || animation.frames.empty())
    return report.finish(out, seconds_since(t0), [&] {
      const auto albedo = material_colours(field);
      return preview_pieces(pieces, &field.zeta, albedo ? &*albedo : nullptr);
    });
  progress("animate", 0.0, std::to_string(animation.frames.size()) + " frames");
  const auto t_animate = Clock::now();
  AnimationTransfer transfer = build_transfer(model, animation, refined.tree, pieces);
  const FramesFormat format = scene.output.frames_format == "obj" ? FramesFormat::kObj : FramesFormat::kBinary;
  if (scene.output.frames) write_frames(pieces, transfer, animation, out, format);
  report.animated(transfer, scene.output.frames ? animation.frames.size() : 0);
  const int sheet = o.preview_frames.value_or(scene.output.preview_frames);
  const std::optional<std::array<Grid3, 3>> albedo =
      scene.output.glb || scene.output.preview || sheet > 0 ? material_colours(field) : std::nullopt;
  const StrengthRamp ramp(field.zeta);
  const FractureColour colour_at = fracture_colour(albedo ? &*albedo : nullptr, ramp);  // preview.png's colours
  if (scene.output.glb)
    report.gltf(write_animation_glb(pieces, transfer, animation, out / "animation.glb",
                                    {.inside_color = colour_at, .color_exterior = albedo.has_value()}));
  if (sheet > 0)
    write_png(out / "preview_frames.png", preview_frames(pieces, transfer, animation, sheet, colour_at));
  report.seconds("animate", seconds_since(t_animate));
  return report.finish(out, seconds_since(t0), [&] { return preview_pieces(pieces, &field.zeta, albedo ? &*albedo : nullptr); });
}

}  // namespace fracref
