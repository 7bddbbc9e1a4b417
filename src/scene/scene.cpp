// The scene schema: which keys each object takes, their defaults and their ranges.
// scenes/SCHEMA.md documents the same; keep the two in step.
#include "scene/scene.hpp"

#include <algorithm>
#include <iterator>
#include <limits>
#include <optional>

#include "scene/json_strict.hpp"

namespace fracref {
namespace {

namespace fs = std::filesystem;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Where the {} / {:0N} field of a frame pattern sits: [begin, end) and the zero-padding N.
struct FrameField {
  std::size_t begin = 0;
  std::size_t end = 0;
  int width = 0;
};

/// Finds the single replacement field, or returns nullopt when the pattern is malformed.
std::optional<FrameField> find_frame_field(const std::string& s) {
  const std::size_t open = s.find('{');
  const std::size_t close = s.find('}');
  if (open == std::string::npos || close == std::string::npos || close < open) return std::nullopt;
  if (s.find_first_of("{}", close + 1) != std::string::npos || s.find('{', open + 1) < close) return std::nullopt;
  const std::string spec = s.substr(open + 1, close - open - 1);
  FrameField f{open, close + 1, 0};
  if (spec.empty()) return f;
  if (spec.size() < 3 || spec.size() > 4 || spec[0] != ':' || spec[1] != '0') return std::nullopt;
  for (std::size_t i = 2; i < spec.size(); ++i) {
    if (spec[i] < '0' || spec[i] > '9') return std::nullopt;
  }
  f.width = std::stoi(spec.substr(2));
  if (f.width < 1 || f.width > 12) return std::nullopt;
  return f;
}

FractureSpec read_fracture(ObjectReader r, const fs::path& dir) {
  FractureSpec f;
  const std::string kind = r.choice_required("kind", {"tets", "pieces", "cuts"});
  f.kind = kind == "tets" ? FractureKind::tets : kind == "pieces" ? FractureKind::pieces : FractureKind::cuts;
  const bool has_mesh = r.has("mesh");
  bool has_files = false;
  if (f.kind == FractureKind::pieces) {
    has_files = r.has("files");
  } else {
    r.forbid("files", "only allowed when kind is 'pieces' (use 'mesh')");
  }
  if (has_mesh && has_files) throw r.error("files", "give either 'mesh' or 'files', not both");
  if (!has_mesh && !has_files) {
    throw r.error("mesh", f.kind == FractureKind::pieces
                              ? "required key is missing (or give 'files', one mesh file per piece)"
                              : "required key is missing");
  }
  if (has_files) f.files = r.paths_required("files", dir);
  if (has_mesh) f.mesh = r.path_required("mesh", dir);
  if (f.kind == FractureKind::tets) {
    f.cracks = r.path("cracks", dir);
  } else {
    r.forbid("cracks", "only allowed when kind is 'tets'");
  }
  f.virtual_fracture = r.boolean("virtual_fracture", true);
  if (f.kind != FractureKind::tets) {
    f.cells_per_diagonal = r.number("cells_per_diagonal", 0.0, Range::closed(4.0, 128.0));
  } else {
    r.forbid("cells_per_diagonal", "only allowed when kind is 'cuts' or 'pieces'");
  }
  if (f.kind == FractureKind::pieces) {
    f.tolerance = r.number("tolerance", f.tolerance, Range{0.0, 0.1, true, false});
  } else {
    r.forbid("tolerance", "only allowed when kind is 'pieces'");
  }
  r.finish();
  return f;
}

AnimationSpec read_animation(ObjectReader r, const fs::path& dir) {
  AnimationSpec a;
  const bool frames = r.choice_required("kind", {"frames", "rigid"}) == "frames";
  a.kind = frames ? AnimationKind::frames : AnimationKind::rigid;
  if (frames) {
    a.frames = r.path_required("frames", dir);
    if (!find_frame_field(r.string_required("frames"))) {
      throw r.error("frames", "must contain exactly one '{}' or '{:0N}' field for the frame number (N in 1..12), got '" +
                                  r.string_required("frames") + "'");
    }
    a.first = r.integer("first", 0, {0, 1000000000});
    a.count = r.integer_required("count", {1, 1000000});
    a.parent_map = r.path("parent_map", dir);
    r.forbid("transforms", "only allowed when kind is 'rigid'");
  } else {
    a.transforms = r.path_required("transforms", dir);
    for (const char* key : {"frames", "first", "count", "parent_map"}) r.forbid(key, "only allowed when kind is 'frames'");
  }
  a.fps = r.number("fps", 24.0, Range::greater_than(0.0));
  r.finish();
  return a;
}

FieldSettings read_field(ObjectReader r, const fs::path& dir) {
  static const std::vector<std::string> types = {"marble", "wood",      "branch",   "brick", "inclusions",
                                                 "perlin", "fbm",       "constant", "grid"};
  FieldSettings f;
  const std::string type = r.choice_required("type", types);
  f.type = FieldType(std::find(types.begin(), types.end(), type) - types.begin());
  const IntRange res_range{2, 1024};
  if (f.type == FieldType::grid) {
    f.resolution = r.uvec3("resolution", glm::uvec3(0), res_range);
    f.file = r.path_required("file", dir);
  } else {
    f.resolution = r.uvec3_required("resolution", res_range);
    r.forbid("file", "only allowed when type is 'grid'");
  }
  // A fraction of the diagonal: more than the exterior's own size on every side only wastes grid cells.
  f.padding = r.number("padding", 0.05, Range::closed(0.0, 1.0));
  f.seed = std::uint64_t(r.integer("seed", 1, IntRange::at_least(0)));
  f.params = r.raw_object("params");
  r.finish();
  return f;
}

WeightsSpec read_weights(ObjectReader r) {
  WeightsSpec w;
  // ζ is in [0, 1] and d/D below 1: weights beyond 1e6 only drown the other terms in rounding.
  w.strength = r.number("strength", w.strength, Range::closed(0.0, 1e6));
  w.distance = r.number("distance", w.distance, Range::closed(0.0, 1e6));
  w.offset = r.number("offset", w.offset, Range::open(0.0, 1e6));
  if (w.strength == 0.0 && w.distance == 0.0) {
    throw r.object_error("'strength' and 'distance' cannot both be 0 (the field would be constant)");
  }
  r.finish();
  return w;
}

PyramidSpec read_pyramid(ObjectReader r) {
  PyramidSpec p;
  p.levels = int(r.integer("levels", p.levels, {1, 8}));
  // The blur's radius is ceil(3 sigma) cells and the pyramid allows at most kMaxBlurRadius (64).
  p.sigma = r.number("sigma", p.sigma, Range{0.0, 20.0, true, false});
  r.finish();
  return p;
}

RefineSpec read_refine(ObjectReader r) {
  RefineSpec f;
  // Fractions of the diagonal (tau, delta, step) and of E (tolerance): 1 and more mean nothing.
  f.tau = r.number("tau", f.tau, Range::open(0.0, 1.0));
  f.delta = r.number("delta", f.delta, Range::open(0.0, 1.0));
  f.step = r.number("step", f.step, Range::half_open(0.0, 1.0));
  f.tolerance = r.number("tolerance", f.tolerance, Range::open(0.0, 1.0));
  f.max_iterations = int(r.integer("max_iterations", f.max_iterations, {0, 100000}));
  f.max_triangles = r.integer("max_triangles", f.max_triangles, {1, 50000000});
  f.seed = std::uint64_t(r.integer("seed", std::int64_t(f.seed), IntRange::at_least(0)));
  f.min_angle = r.number("min_angle", f.min_angle, Range::half_open(0.0, 60.0));
  f.collisions = r.boolean("collisions", f.collisions);
  f.rim_motion = r.boolean("rim_motion", f.rim_motion);
  f.tangential_motion = r.boolean("tangential_motion", f.tangential_motion);
  f.relax = r.number("relax", f.relax, Range::closed(0.0, 1.0));
  if (r.has("rim_smoothing")) f.rim_smoothing = int(r.integer("rim_smoothing", 0, {0, 1000}));
  f.fold_solves = int(r.integer("fold_solves", f.fold_solves, {1, 8}));
  f.hairpin_collapse = r.number("hairpin_collapse", f.hairpin_collapse, Range::closed(0.0, 90.0));
  r.finish();
  return f;
}

OutputSpec read_output(ObjectReader r) {
  OutputSpec o;
  o.ply = r.boolean("ply", o.ply);
  o.obj = r.boolean("obj", o.obj);
  o.glb = r.boolean("glb", o.glb);
  o.frames = r.boolean("frames", o.frames);
  o.frames_format = r.choice("frames_format", {"bin", "obj"}, o.frames_format);
  o.preview = r.boolean("preview", o.preview);
  o.preview_frames = int(r.integer("preview_frames", o.preview_frames, {0, 1000}));
  r.finish();
  return o;
}

fs::path absolute_normal(const fs::path& file) {
  return (file.empty() ? fs::current_path() : fs::absolute(file)).lexically_normal();
}

}  // namespace

Scene parse_scene(const nlohmann::json& json, const fs::path& file) {
  ObjectReader root(json, file.string(), "");
  Scene s;
  s.file = absolute_normal(file);
  const fs::path dir = s.file.parent_path();
  root.string("$schema", "");  // annotations, ignored
  root.string("comment", "");
  s.name = root.string("name", file.stem().string());
  if (s.name.empty()) throw root.error("name", "must not be empty");
  s.exterior = root.path_required("exterior", dir);
  s.fracture = read_fracture(root.object_required("fracture"), dir);
  if (auto a = root.object("animation")) s.animation = read_animation(std::move(*a), dir);
  s.field = read_field(root.object_required("field"), dir);
  if (auto w = root.object("weights")) s.weights = read_weights(std::move(*w));
  if (auto p = root.object("pyramid")) s.pyramid = read_pyramid(std::move(*p));
  if (auto r = root.object("refine")) s.refine = read_refine(std::move(*r));
  if (auto o = root.object("output")) s.output = read_output(std::move(*o));
  root.finish();
  return s;
}

Scene load_scene(const fs::path& file) { return parse_scene(read_json_file(file), file); }

fs::path frame_path(const fs::path& pattern, std::int64_t frame) {
  const std::string s = pattern.string();
  const std::optional<FrameField> f = find_frame_field(s);
  if (!f) return pattern;
  std::string number = std::to_string(frame < 0 ? -frame : frame);
  if (int(number.size()) < f->width) number.insert(0, std::size_t(f->width) - number.size(), '0');
  if (frame < 0) number.insert(0, 1, '-');
  return s.substr(0, f->begin) + number + s.substr(f->end);
}

const char* to_string(FractureKind kind) {
  switch (kind) {
    case FractureKind::tets: return "tets";
    case FractureKind::pieces: return "pieces";
    case FractureKind::cuts: return "cuts";
  }
  return "?";
}

const char* to_string(AnimationKind kind) {
  switch (kind) {
    case AnimationKind::none: return "none";
    case AnimationKind::frames: return "frames";
    case AnimationKind::rigid: return "rigid";
  }
  return "?";
}

const char* to_string(FieldType type) {
  static const char* names[] = {"marble", "wood", "branch", "brick", "inclusions", "perlin", "fbm", "constant", "grid"};
  const auto i = std::size_t(type);
  return i < std::size(names) ? names[i] : "?";
}

}  // namespace fracref
