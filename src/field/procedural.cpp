#include "field/procedural.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "field/materials.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

bool finite_vec(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string format_vec(glm::dvec3 v) {
  std::ostringstream out;
  out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
  return out.str();
}

// Collects nothing: the first bad parameter throws, named as "<group>.<member>".
class ParamCheck {
 public:
  explicit ParamCheck(std::string group) : group_(std::move(group)) {}

  void positive(const char* name, double v) const { require(name, std::isfinite(v) && v > 0, "> 0", v); }
  void non_negative(const char* name, double v) const { require(name, std::isfinite(v) && v >= 0, ">= 0", v); }
  void at_least_one(const char* name, double v) const { require(name, std::isfinite(v) && v >= 1, ">= 1", v); }
  void unit(const char* name, double v) const {
    require(name, std::isfinite(v) && v >= 0 && v <= 1, "in [0, 1]", v);
  }
  void finite(const char* name, double v) const { require(name, std::isfinite(v), "finite", v); }
  void octaves(const char* name, int v) const { require(name, v >= 1 && v <= 16, "in 1..16", v); }
  void direction(const char* name, glm::dvec3 v) const {
    const bool ok = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) &&
                    glm::dot(v, v) > 0.0;
    if (!ok) fail(name, "a finite non-zero vector", format_vec(v));
  }
  void require(const char* name, bool ok, const char* what, double v) const {
    if (!ok) fail(name, what, format_number(v));
  }
  [[noreturn]] void fail(const char* name, const std::string& what, const std::string& got) const {
    const std::string key = group_.empty() ? name : group_ + "." + name;
    throw InputError("field params: '" + key + "' must be " + what + " (got " + got + ")");
  }

 private:
  std::string group_;
};

void check_fbm(const FbmParams& p, bool octaves_used) {
  const ParamCheck c("fbm");
  c.positive("contrast", p.contrast);
  if (!octaves_used) return;
  c.octaves("octaves", p.octaves);
  c.positive("lacunarity", p.lacunarity);
  c.positive("gain", p.gain);
}

void check_marble(const MarbleParams& p) {
  const ParamCheck c("marble");
  c.direction("vein_direction", p.vein_direction);
  c.non_negative("distortion", p.distortion);
  c.octaves("turbulence_octaves", p.turbulence_octaves);
  c.require("threshold", std::isfinite(p.threshold) && std::abs(p.threshold) < 1, "in (-1, 1)",
            p.threshold);
  c.positive("edge", p.edge);
  c.unit("white_min", p.white_min);
  c.unit("white_max", p.white_max);
  c.unit("blue_min", p.blue_min);
  c.unit("blue_max", p.blue_max);
  c.positive("white_frequency", p.white_frequency);
  c.positive("grain_frequency", p.grain_frequency);
}

void check_wood(const WoodParams& p, bool rings) {
  const ParamCheck c("wood");
  c.direction("axis", p.axis);
  if (p.axis_point) {
    const glm::dvec3 a = *p.axis_point;
    if (!(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z)))
      c.fail("axis_point", "finite", format_vec(a));
  }
  c.non_negative("radius", p.radius);
  c.unit("core_strength", p.core_strength);
  c.unit("surface_strength", p.surface_strength);
  c.positive("radial_exponent", p.radial_exponent);
  c.at_least_one("elongation", p.elongation);
  c.unit("noise_amplitude", p.noise_amplitude);
  c.octaves("noise_octaves", p.noise_octaves);
  if (!rings) return;
  c.unit("ring_amplitude", p.ring_amplitude);
  c.positive("ring_count", p.ring_count);
  c.non_negative("ring_wobble", p.ring_wobble);
}

void check_brick(const BrickParams& p) {
  const ParamCheck c("brick");
  const glm::dvec3 b = p.brick_size;
  if (!(finite_vec(b) && b.x > 0 && b.y > 0 && b.z >= 0))
    c.fail("brick_size", "(> 0, > 0, >= 0)", format_vec(b));
  c.positive("mortar", p.mortar);
  c.finite("bond_offset", p.bond_offset);
  c.unit("brick_strength", p.brick_strength);
  c.unit("mortar_strength", p.mortar_strength);
  c.unit("interface_strength", p.interface_strength);
  c.positive("band", p.band);
  c.unit("noise_amplitude", p.noise_amplitude);
}

void check_inclusions(const InclusionParams& p) {
  const ParamCheck c("inclusions");
  c.require("count", p.count >= 0 && p.count <= 10000, "in 0..10000", p.count);
  c.positive("size_min", p.size_min);
  c.require("size_max", std::isfinite(p.size_max) && p.size_max >= p.size_min, ">= size_min",
            p.size_max);
  c.unit("matrix_strength", p.matrix_strength);
  c.unit("inclusion_strength", p.inclusion_strength);
  c.positive("edge", p.edge);
  c.unit("noise_amplitude", p.noise_amplitude);
}

bool box_is_set(const FieldSpec& spec) {
  return spec.object_min.x <= spec.object_max.x && spec.object_min.y <= spec.object_max.y &&
         spec.object_min.z <= spec.object_max.z;
}

detail::MaterialFrame frame_of(const FieldSpec& spec) {
  if (!box_is_set(spec))
    throw InputError("field: the object's bounding box (object_min, object_max) is not set");
  return detail::make_frame(spec, spec.object_min, spec.object_max);
}

// The uniform cell and the centred origin documented in procedural.hpp.
void place_grid(Grid3& grid, glm::dvec3 lo, glm::dvec3 hi) {
  const glm::dvec3 extent = hi - lo;
  double cell = 0.0;
  for (int a = 0; a < 3; ++a)
    if (grid.dims[a] > 1) cell = std::max(cell, extent[a] / double(grid.dims[a] - 1));
  if (grid.dims.x == 1 && grid.dims.y == 1 && grid.dims.z == 1) {
    const double largest = std::max({extent.x, extent.y, extent.z});
    cell = largest > 0.0 ? largest : 1.0;
  }
  if (!(cell > 0.0) || !std::isfinite(cell))
    throw InputError("field grid: the box " + format_vec(lo) + " - " + format_vec(hi) +
                     " has no extent along any axis with more than one node");
  grid.cell = cell;
  for (int a = 0; a < 3; ++a) {
    const bool spans = grid.dims[a] > 1 && extent[a] / double(grid.dims[a] - 1) == cell;
    grid.origin[a] = spans ? lo[a] : 0.5 * (lo[a] + hi[a]) - 0.5 * cell * double(grid.dims[a] - 1);
  }
}

void fill_slices(Grid3& grid, const detail::Material& material, unsigned first, unsigned step) {
  for (unsigned z = first; z < grid.dims.z; z += step)
    for (unsigned y = 0; y < grid.dims.y; ++y)
      for (unsigned x = 0; x < grid.dims.x; ++x)
        grid.values[grid.index(x, y, z)] =
            static_cast<float>(material.strength(grid.node_position(x, y, z)));
}

}  // namespace

namespace detail {

MaterialFrame make_frame(const FieldSpec& spec, glm::dvec3 box_min, glm::dvec3 box_max) {
  if (!finite_vec(box_min) || !finite_vec(box_max) || box_min.x > box_max.x ||
      box_min.y > box_max.y || box_min.z > box_max.z)
    throw InputError("field: the bounding box " + format_vec(box_min) + " - " + format_vec(box_max) +
                     " is not finite or not ordered min <= max");
  MaterialFrame f;
  f.min = box_min;
  f.max = box_max;
  f.centre = 0.5 * (box_min + box_max);
  f.diagonal = glm::length(box_max - box_min);
  if (!(f.diagonal > 0.0))
    throw InputError("field: the bounding box " + format_vec(box_min) + " is a single point");
  f.feature = effective_scale(spec) * f.diagonal;
  std::uint64_t state = spec.seed ^ 0x243F6A8885A308D3ULL;
  for (int a = 0; a < 3; ++a) f.offset[a] = double(splitmix64(state) >> 11) * 0x1.0p-53 * 256.0;
  return f;
}

}  // namespace detail

const std::vector<std::string>& field_type_names() {
  static const std::vector<std::string> names = {"constant", "perlin", "fbm",   "marble",
                                                 "wood",     "branch", "brick", "inclusions"};
  return names;
}

double effective_scale(const FieldSpec& spec) {
  if (spec.scale > 0.0) return spec.scale;
  const std::string& t = spec.type;
  if (t == "marble") return 0.2;
  if (t == "wood" || t == "branch" || t == "inclusions") return 0.1;
  if (t == "brick") return 0.05;
  return 0.25;
}

void validate_field_spec(const FieldSpec& spec) {
  const auto& names = field_type_names();
  if (std::find(names.begin(), names.end(), spec.type) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw InputError("field: unknown type '" + spec.type + "' (known: " + known + ")");
  }
  ParamCheck("").non_negative("scale", spec.scale);
  const std::string& t = spec.type;
  if (t == "constant") ParamCheck("").finite("value", spec.value);
  if (t == "fbm" || t == "perlin") check_fbm(spec.fbm, t == "fbm");
  if (t == "marble") check_marble(spec.marble);
  if (t == "wood" || t == "branch") check_wood(spec.wood, t == "wood");
  if (t == "brick") check_brick(spec.brick);
  if (t == "inclusions") check_inclusions(spec.inclusions);
}

double strength_at(const FieldSpec& spec, const PerlinNoise& noise, glm::dvec3 p_material) {
  validate_field_spec(spec);
  const detail::MaterialFrame frame = frame_of(spec);
  return detail::make_material(spec, noise, frame)->strength(p_material);
}

Grid3 sample_strength(const FieldSpec& spec, glm::dvec3 bbox_min, glm::dvec3 bbox_max,
                      glm::uvec3 resolution, unsigned threads) {
  validate_field_spec(spec);
  if (resolution.x == 0 || resolution.y == 0 || resolution.z == 0)
    throw InputError("field grid: resolution must be at least 1 node per axis (got " +
                     std::to_string(resolution.x) + " x " + std::to_string(resolution.y) + " x " +
                     std::to_string(resolution.z) + ")");
  if (double(resolution.x) * resolution.y * resolution.z > double(1u << 31))
    throw InputError("field grid: more than 2^31 nodes requested");
  if (!finite_vec(bbox_min) || !finite_vec(bbox_max) || bbox_min.x > bbox_max.x ||
      bbox_min.y > bbox_max.y || bbox_min.z > bbox_max.z)
    throw InputError("field grid: the box " + format_vec(bbox_min) + " - " + format_vec(bbox_max) +
                     " is not finite or not ordered min <= max");
  Grid3 grid;
  grid.dims = resolution;
  place_grid(grid, bbox_min, bbox_max);
  grid.values.assign(grid.size(), 0.0f);

  const detail::MaterialFrame frame = box_is_set(spec) ? frame_of(spec)
                                                        : detail::make_frame(spec, bbox_min, bbox_max);
  const PerlinNoise noise(spec.seed);
  const auto material = detail::make_material(spec, noise, frame);
  const unsigned n = std::clamp(threads == 0 ? unsigned(default_threads()) : threads, 1u, resolution.z);
  // Chunk t fills the z-slices t, t+n, ... (interleaved, so that each thread samples every part of the box);
  // each slice is computed on its own, so the values never depend on how many threads ran.
  parallel_chunks(n, n, int(n),
                  [&](std::size_t t, std::size_t, std::size_t) { fill_slices(grid, *material, unsigned(t), n); });
  return grid;
}

std::optional<std::array<Grid3, 3>> sample_albedo(const FieldSpec& spec, const Grid3& like, unsigned threads) {
  validate_field_spec(spec);
  const PerlinNoise noise(spec.seed);
  const auto material = detail::make_material(spec, noise, frame_of(spec));
  if (!material->albedo(spec.object_min)) return std::nullopt;
  std::array<Grid3, 3> rgb;
  for (Grid3& g : rgb) g = like, g.values.assign(like.size(), 0.0f);
  const unsigned n = std::clamp(threads == 0 ? unsigned(default_threads()) : threads, 1u, std::max(like.dims.z, 1u));
  parallel_chunks(n, n, int(n), [&](std::size_t t, std::size_t, std::size_t) {
    for (unsigned z = unsigned(t); z < like.dims.z; z += n)
      for (unsigned y = 0; y < like.dims.y; ++y)
        for (unsigned x = 0; x < like.dims.x; ++x) {
          const glm::vec3 c = *material->albedo(like.node_position(x, y, z));
          for (int k = 0; k < 3; ++k) rgb[std::size_t(k)].values[like.index(x, y, z)] = c[k];
        }
  });
  return rgb;
}

std::vector<InclusionCube> inclusion_cubes(const FieldSpec& spec) {
  validate_field_spec(spec);
  check_inclusions(spec.inclusions);
  return detail::make_inclusion_cubes(spec, frame_of(spec));
}

double marble_blue_weight(const FieldSpec& spec, const PerlinNoise& noise, glm::dvec3 p_material) {
  validate_field_spec(spec);
  check_marble(spec.marble);
  return detail::marble_weight(spec.marble, noise, frame_of(spec), p_material);
}

}  // namespace fracref
