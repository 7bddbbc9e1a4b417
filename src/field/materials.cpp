#include "field/materials.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fracref::detail {
namespace {

constexpr double kTwoPi = 6.283185307179586;
// Fixed shifts that decorrelate the several noises one material reads from the same table.
constexpr glm::dvec3 kShiftA{17.31, 43.97, 71.13};
constexpr glm::dvec3 kShiftB{113.7, 5.19, 29.43};

double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }
double noise01(double n) { return clamp01(0.5 + 0.5 * n); }
double lerp(double a, double b, double t) { return a + t * (b - a); }
double smoothstep(double e0, double e1, double x) {
  const double t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3.0 - 2.0 * t);
}

double uniform01(std::uint64_t& state) { return double(splitmix64(state) >> 11) * 0x1.0p-53; }

glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, double t) { return a + float(std::clamp(t, 0.0, 1.0)) * (b - a); }

// Colours (linear RGB) of the phases of the materials that have colours of their own, as the
// paper's pictures show them. The others (constant, clay, brick) have none: a crack along the
// wall's brick-mortar interface has no one colour, and ζ's ramp shows it better.
const glm::vec3 kMarbleWhite{0.86f, 0.86f, 0.83f}, kMarbleBlue{0.12f, 0.22f, 0.52f};
const glm::vec3 kHeartwood{0.36f, 0.20f, 0.08f}, kSapwood{0.82f, 0.64f, 0.40f};
const glm::vec3 kJelly{0.62f, 0.04f, 0.10f};
const glm::vec3 kFruit[] = {{0.98f, 0.55f, 0.05f}, {0.35f, 0.75f, 0.12f}, {0.98f, 0.85f, 0.15f},
                            {0.45f, 0.12f, 0.45f}, {0.98f, 0.70f, 0.45f}, {0.95f, 0.95f, 0.80f}};

class Constant final : public Material {
 public:
  explicit Constant(double value) : value_(value) {}
  double strength(glm::dvec3) const override { return value_; }

 private:
  double value_;
};

class Fbm final : public Material {
 public:
  Fbm(const FbmParams& params, const PerlinNoise& noise, const MaterialFrame& frame)
      : params_(params), noise_(noise), frame_(frame) {}
  double strength(glm::dvec3 p) const override {
    return noise01(params_.contrast * fbm(noise_, frame_.noise_coords(p), params_.octaves,
                                          params_.lacunarity, params_.gain));
  }

 private:
  FbmParams params_;
  const PerlinNoise& noise_;
  MaterialFrame frame_;
};

class Marble final : public Material {
 public:
  Marble(const MarbleParams& params, const PerlinNoise& noise, const MaterialFrame& frame)
      : params_(params), noise_(noise), frame_(frame) {}
  double strength(glm::dvec3 p) const override {
    const double w = marble_weight(params_, noise_, frame_, p);
    const glm::dvec3 q = frame_.noise_coords(p);
    const double white = lerp(params_.white_min, params_.white_max,
                              noise01(noise_(q * params_.white_frequency + kShiftA)));
    const double blue = lerp(params_.blue_min, params_.blue_max,
                             noise01(noise_(q * params_.grain_frequency + kShiftB)));
    return lerp(white, blue, w);
  }
  // White marble and blue veins, each shaded a little by its own noise (the grains in the blue).
  std::optional<glm::vec3> albedo(glm::dvec3 p) const override {
    const double w = marble_weight(params_, noise_, frame_, p);
    const glm::dvec3 q = frame_.noise_coords(p);
    const double white = noise01(noise_(q * params_.white_frequency + kShiftA));
    const double grain = noise01(noise_(q * params_.grain_frequency + kShiftB));
    return mix(kMarbleWhite * float(0.9 + 0.1 * white), kMarbleBlue * float(0.7 + 0.6 * grain), w);
  }

 private:
  MarbleParams params_;
  const PerlinNoise& noise_;
  MaterialFrame frame_;
};

// An orthonormal frame (e1, e2, axis), e1 built from the coordinate axis least aligned with
// the cylinder axis so that it is well conditioned and deterministic.
struct CylinderFrame {
  glm::dvec3 e1, e2, axis;
};

CylinderFrame cylinder_frame(glm::dvec3 axis) {
  const glm::dvec3 a = glm::normalize(axis);
  const glm::dvec3 abs_a = glm::abs(a);
  glm::dvec3 helper{1.0, 0.0, 0.0};
  if (abs_a.y <= abs_a.x && abs_a.y <= abs_a.z) helper = {0.0, 1.0, 0.0};
  else if (abs_a.z <= abs_a.x && abs_a.z <= abs_a.y) helper = {0.0, 0.0, 1.0};
  const glm::dvec3 e1 = glm::normalize(glm::cross(a, helper));
  return {e1, glm::cross(a, e1), a};
}

// The radius of the largest circle about the box's centre line inside the box's projection on
// the plane (e1, e2); for an axis-aligned cylinder's box, the cylinder's radius.
double inscribed_radius(const CylinderFrame& f, const MaterialFrame& frame) {
  const glm::dvec3 half = 0.5 * (frame.max - frame.min);
  const double h1 = glm::dot(half, glm::abs(f.e1));
  const double h2 = glm::dot(half, glm::abs(f.e2));
  const double r = std::min(h1, h2);
  return r > 0.0 ? r : std::max(h1, h2);
}

class Wood final : public Material {
 public:
  Wood(const WoodParams& params, bool rings, const PerlinNoise& noise, const MaterialFrame& frame)
      : params_(params), noise_(noise), frame_(frame), cyl_(cylinder_frame(params.axis)) {
    if (!rings) params_.ring_amplitude = 0.0;
    point_ = params.axis_point.value_or(frame.centre);
    radius_ = params.radius > 0.0 ? params.radius * frame.diagonal : inscribed_radius(cyl_, frame);
    if (!(radius_ > 0.0)) radius_ = frame.diagonal;  // a box of one point across the axis
  }
  double strength(glm::dvec3 p) const override {
    const glm::dvec3 rel = p - point_;
    const glm::dvec3 local{glm::dot(rel, cyl_.e1), glm::dot(rel, cyl_.e2), glm::dot(rel, cyl_.axis)};
    const double r = std::sqrt(local.x * local.x + local.y * local.y) / radius_;
    // Elongated noise: the axial coordinate shrinks, so features stretch along the axis.
    const glm::dvec3 q =
        glm::dvec3(local.x, local.y, local.z / params_.elongation) / frame_.feature + frame_.offset;
    const double radial = lerp(params_.core_strength, params_.surface_strength,
                               std::pow(std::min(r, 1.0), params_.radial_exponent));
    const double a_r = params_.ring_amplitude;
    double value = (1.0 - a_r) * radial + params_.noise_amplitude * fbm(noise_, q, params_.noise_octaves);
    if (a_r > 0.0) {
      const double phase = params_.ring_count * r + params_.ring_wobble * noise_(q + kShiftA);
      value += a_r * (0.5 + 0.5 * std::cos(kTwoPi * phase));
    }
    return clamp01(value);
  }
  // Dark heartwood at the axis to pale sapwood under the bark, as ζ rises.
  std::optional<glm::vec3> albedo(glm::dvec3 p) const override { return mix(kHeartwood, kSapwood, strength(p)); }

 private:
  WoodParams params_;
  const PerlinNoise& noise_;
  MaterialFrame frame_;
  CylinderFrame cyl_;
  glm::dvec3 point_{0.0};
  double radius_ = 1.0;
};

// Distance from a point outside (or on) an axis-aligned box to it.
double box_distance(glm::dvec3 a, glm::dvec3 lo, glm::dvec3 hi) {
  return glm::length(glm::max(glm::max(lo - a, a - hi), glm::dvec3(0.0)));
}

class Brick final : public Material {
 public:
  Brick(const BrickParams& params, const PerlinNoise& noise, const MaterialFrame& frame)
      : params_(params), noise_(noise), frame_(frame) {
    size_ = params.brick_size * frame.diagonal;
    through_ = !(params.brick_size.z > 0.0);
    mortar_ = params.mortar * frame.diagonal;
    band_ = params.band * frame.diagonal;
    pitch_ = size_ + glm::dvec3(mortar_);
  }
  double strength(glm::dvec3 p) const override {
    bool inside = false;
    const double d = interface_distance(p - frame_.min, inside);
    const double t = d / band_;
    const double w = t < 1.0 ? (1.0 - t * t) * (1.0 - t * t) : 0.0;
    const double base = inside ? params_.brick_strength : params_.mortar_strength;
    return clamp01(lerp(base, params_.interface_strength, w) +
                   params_.noise_amplitude * noise_(frame_.noise_coords(p)));
  }

 private:
  double course_shift(double j) const { return j * params_.bond_offset * pitch_.x; }

  // Distance from `a` (relative to the first brick's corner) to the nearest brick surface.
  double interface_distance(glm::dvec3 a, bool& inside) const {
    const double j0 = std::floor(a.y / pitch_.y);
    const double i0 = std::floor((a.x - course_shift(j0)) / pitch_.x);
    const double k0 = through_ ? 0.0 : std::floor(a.z / pitch_.z);
    const glm::dvec3 local = a - glm::dvec3(i0 * pitch_.x + course_shift(j0), j0 * pitch_.y,
                                            k0 * pitch_.z);
    inside = local.x <= size_.x && local.y <= size_.y && (through_ || local.z <= size_.z);
    if (inside) {
      double d = std::min({local.x, size_.x - local.x, local.y, size_.y - local.y});
      if (!through_) d = std::min({d, local.z, size_.z - local.z});
      return d;
    }
    return mortar_distance(a, j0, k0);
  }

  // In mortar: the nearest brick is in this course or the next one down or up, at this or the
  // next brick along x, at this or the next layer along z.
  double mortar_distance(glm::dvec3 a, double j0, double k0) const {
    double best = std::numeric_limits<double>::infinity();
    for (double j = j0 - 1; j <= j0 + 1; ++j) {
      const double shift = course_shift(j);
      const double ic = std::floor((a.x - shift) / pitch_.x);
      for (double i = ic; i <= ic + 1; ++i) {
        for (double k = k0; k <= k0 + (through_ ? 0 : 1); ++k) {
          glm::dvec3 lo{i * pitch_.x + shift, j * pitch_.y, k * pitch_.z};
          glm::dvec3 hi = lo + size_;
          if (through_) lo.z = hi.z = a.z;  // bricks through the wall: no z faces
          best = std::min(best, box_distance(a, lo, hi));
        }
      }
    }
    return best;
  }

  BrickParams params_;
  const PerlinNoise& noise_;
  MaterialFrame frame_;
  glm::dvec3 size_{0.0}, pitch_{0.0};
  bool through_ = true;
  double mortar_ = 0.0, band_ = 0.0;
};

// Signed distance to a cube (negative inside).
double cube_signed_distance(const InclusionCube& c, glm::dvec3 p) {
  const glm::dvec3 local = glm::transpose(c.rotation) * (p - c.centre);
  const glm::dvec3 q = glm::abs(local) - glm::dvec3(c.half_size);
  const double outside = glm::length(glm::max(q, glm::dvec3(0.0)));
  return outside + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

class Inclusions final : public Material {
 public:
  Inclusions(const FieldSpec& spec, const PerlinNoise& noise, const MaterialFrame& frame)
      : params_(spec.inclusions), noise_(noise), frame_(frame),
        cubes_(make_inclusion_cubes(spec, frame)) {
    edge_ = params_.edge * frame.diagonal;
  }
  double strength(glm::dvec3 p) const override {
    std::size_t nearest = 0;
    const double w = smoothstep(edge_, -edge_, cube_distance(p, nearest));
    return clamp01(lerp(params_.matrix_strength, params_.inclusion_strength, w) +
                   params_.noise_amplitude * noise_(frame_.noise_coords(p)));
  }
  // Red jelly; each cube a fruit of its own colour (the nearest cube's, where cubes overlap).
  std::optional<glm::vec3> albedo(glm::dvec3 p) const override {
    std::size_t nearest = 0;
    const double w = smoothstep(edge_, -edge_, cube_distance(p, nearest));
    return mix(kJelly, kFruit[nearest % (sizeof kFruit / sizeof kFruit[0])], w);
  }

 private:
  // The signed distance to the nearest cube, capped at edge_ (beyond it w is 0), and that cube.
  // Only cubes whose bounding sphere reaches within the blend band can be nearer.
  double cube_distance(glm::dvec3 p, std::size_t& nearest) const {
    double sd = edge_;
    for (std::size_t k = 0; k < cubes_.size(); ++k) {
      const InclusionCube& c = cubes_[k];
      const double reach = c.half_size * 1.7320508075688772 + edge_;
      const glm::dvec3 v = p - c.centre;
      if (glm::dot(v, v) >= reach * reach) continue;
      if (const double d = cube_signed_distance(c, p); d < sd) sd = d, nearest = k;
    }
    return sd;
  }

  InclusionParams params_;
  const PerlinNoise& noise_;
  MaterialFrame frame_;
  std::vector<InclusionCube> cubes_;
  double edge_ = 0.0;
};

// A uniformly random rotation from three uniforms (Shoemake 1992, via a unit quaternion).
glm::dmat3 random_rotation(std::uint64_t& state) {
  const double u1 = uniform01(state), u2 = uniform01(state), u3 = uniform01(state);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double x = a * std::sin(kTwoPi * u2), y = a * std::cos(kTwoPi * u2);
  const double z = b * std::sin(kTwoPi * u3), w = b * std::cos(kTwoPi * u3);
  // Columns of the rotation matrix of the quaternion (w, x, y, z).
  return glm::dmat3(glm::dvec3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
                    glm::dvec3(2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
                    glm::dvec3(2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)));
}

}  // namespace

double marble_weight(const MarbleParams& params, const PerlinNoise& noise,
                     const MaterialFrame& frame, glm::dvec3 p) {
  const double u = glm::dot(p - frame.centre, glm::normalize(params.vein_direction)) / frame.feature;
  const double t = turbulence(noise, frame.noise_coords(p), params.turbulence_octaves);
  const double m = std::sin(kTwoPi * (u + params.distortion * t));
  return smoothstep(params.threshold - params.edge, params.threshold + params.edge, m);
}

std::vector<InclusionCube> make_inclusion_cubes(const FieldSpec& spec, const MaterialFrame& frame) {
  const InclusionParams& params = spec.inclusions;
  std::uint64_t state = spec.seed ^ 0x6A09E667F3BCC909ULL;  // a stream apart from the noise's
  std::vector<InclusionCube> cubes;
  cubes.reserve(std::size_t(params.count));
  for (int n = 0; n < params.count; ++n) {
    InclusionCube c;
    c.half_size = 0.5 * frame.diagonal * lerp(params.size_min, params.size_max, uniform01(state));
    const double reach = params.rotate ? c.half_size * 1.7320508075688772 : c.half_size;
    for (int a = 0; a < 3; ++a) {
      const double room = frame.max[a] - frame.min[a] - 2.0 * reach;
      const double u = uniform01(state);
      c.centre[a] = room > 0.0 ? frame.min[a] + reach + u * room : frame.centre[a];
    }
    c.rotation = params.rotate ? random_rotation(state) : glm::dmat3(1.0);
    cubes.push_back(c);
  }
  return cubes;
}

std::unique_ptr<Material> make_material(const FieldSpec& spec, const PerlinNoise& noise,
                                        const MaterialFrame& frame) {
  const std::string& t = spec.type;
  if (t == "constant") return std::make_unique<Constant>(spec.value);
  if (t == "perlin") {
    FbmParams one_octave = spec.fbm;
    one_octave.octaves = 1;
    return std::make_unique<Fbm>(one_octave, noise, frame);
  }
  if (t == "fbm") return std::make_unique<Fbm>(spec.fbm, noise, frame);
  if (t == "marble") return std::make_unique<Marble>(spec.marble, noise, frame);
  if (t == "wood" || t == "branch") return std::make_unique<Wood>(spec.wood, t == "wood", noise, frame);
  if (t == "brick") return std::make_unique<Brick>(spec.brick, noise, frame);
  return std::make_unique<Inclusions>(spec, noise, frame);  // "inclusions": validated before
}

}  // namespace fracref::detail
