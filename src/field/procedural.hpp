#pragma once
// Procedural material-strength fields ζ(x) (paper section 4.2 and the materials of section 6):
// HIGH ζ = hard to break, LOW ζ = weak. The refiner moves the fracture surface toward low
// ψ = w_ζ·ζ + w_d·d + ψ0, so every material below is normalised to [0, 1] (its exact bounds are
// documented with its parameters; values are clamped to [0, 1] where parameters could push
// them out).
//
// Coordinates and sizes. Points are in material space, in scene units. Every length parameter
// (`scale`, brick sizes, radii, bands, cube sizes) is a FRACTION OF THE DIAGONAL of the
// object's bounding box (FieldSpec::object_min/max), so one spec works on any object size.
// Noise is evaluated at q = (p - box centre) / (scale · diagonal) + o(seed), where o(seed) is a
// seeded offset in [0, 256)^3: one noise lattice cell is `scale · diagonal` wide. `scale` 0 (the
// default) takes the type's own default (effective_scale()). Plain noise has a standard deviation
// of about 0.27 and fBm of 3-5 octaves about 0.17; "noise" below is the seeded improved noise.
//
// Member names of the parameter structs are the intended keys of the scene file's `params`
// object (the scene loader maps JSON to FieldSpec; nothing here parses JSON).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "field/grid.hpp"
#include "field/noise.hpp"

namespace fracref {

/// Parameters of the `fbm` type (plain fBm mapped to [0, 1]); `perlin` uses only `contrast`.
struct FbmParams {
  int octaves = 4;          ///< 1..16
  double lacunarity = 2.0;  ///< frequency ratio between octaves, > 0
  double gain = 0.5;        ///< amplitude ratio between octaves, > 0
  double contrast = 1.0;    ///< ζ = clamp(0.5 + 0.5·contrast·fbm, 0, 1); 1 = plain mapping, > 0
};

/// `marble` (the paper's bunny). Stripes m = sin(2π(u + distortion·T(q))), with u the distance
/// along `vein_direction` in units of scale·diagonal and T the turbulence of
/// `turbulence_octaves` octaves, split space into BLUE veins (weight
/// w = smoothstep(threshold - edge, threshold + edge, m) → 1) and WHITE marble (w → 0). White: soft and smooth, low-frequency noise; blue: hard, fine grains of noise at
/// `grain_frequency` times the base frequency.
///   ζ = (1-w)·lerp(white_min, white_max, n01(q·white_frequency))
///       + w·lerp(blue_min, blue_max, n01(q·grain_frequency)),  n01 = clamp(0.5 + 0.5·noise, 0, 1).
/// Range: [min(white_min, blue_min), max(white_max, blue_max)] = [0.05, 1] with the defaults.
struct MarbleParams {
  glm::dvec3 vein_direction{1.0, 0.0, 0.0};  ///< stripes are perpendicular to it; non-zero
  double distortion = 2.0;        ///< turbulence added to the stripe phase, in periods, >= 0
  int turbulence_octaves = 5;     ///< 1..16
  double threshold = 0.5;         ///< m above it is blue (≈ 1/3 of space for 0.5), in (-1, 1)
  double edge = 0.1;              ///< half-width of the blue/white blend in m, > 0
  double white_min = 0.05, white_max = 0.4;  ///< soft white marble
  double blue_min = 0.6, blue_max = 1.0;     ///< hard blue grains
  double white_frequency = 1.0;   ///< low frequency, relative to 1/(scale·diagonal), > 0
  double grain_frequency = 5.0;   ///< high frequency of the blue grains, > 0
};

/// `wood` and `branch` (the paper's tree branch): a cylinder about an axis, SOFT at the axis and
/// HARD at its surface, with Perlin noise ELONGATED along the axis (the axial coordinate divided
/// by `elongation`) so that weak valleys, hence fractures, run along the axis. `wood` adds growth
/// rings; `branch` ignores the ring parameters (ring amplitude 0).
///   r = distance to the axis / R (clamped to [0, 1] for the profile),
///   radial = lerp(core_strength, surface_strength, r^radial_exponent),
///   ring = 0.5 + 0.5·cos(2π(ring_count·r + ring_wobble·noise)),
///   ζ = clamp((1 - ring_amplitude)·radial + ring_amplitude·ring
///       + noise_amplitude·fbm(elongated q, noise_octaves), 0, 1)     (fbm signed, std ≈ 0.17),
/// with the elongated q = (p - axis_point) in an orthonormal frame (e1, e2, axis), its axial
/// component divided by `elongation`, all over scale·diagonal, plus o(seed).
/// Range: [max(0, (1-a_r)·min(core, surface) - a_n·1.0364),
///         min(1, (1-a_r)·max(core, surface) + a_r + a_n·1.0364)] (a_r = 0 for branch);
/// [0, 1] with the defaults (the clamp acts only on rare noise extremes).
struct WoodParams {
  glm::dvec3 axis{0.0, 0.0, 1.0};          ///< direction of the cylinder axis; non-zero
  std::optional<glm::dvec3> axis_point;    ///< a point on the axis (scene units); default: the box centre
  /// Cylinder radius R (fraction of the diagonal); 0 = the inscribed radius of the box's
  /// projection across the axis (the radius itself for an axis-aligned cylinder's box).
  double radius = 0.0;
  double core_strength = 0.15;    ///< ζ profile at the axis, in [0, 1]
  double surface_strength = 0.85; ///< ζ profile at radius R and beyond, in [0, 1]
  double radial_exponent = 1.0;   ///< shape of the profile, > 0
  double elongation = 8.0;        ///< noise stretch along the axis, >= 1
  double noise_amplitude = 0.3;   ///< in [0, 1]
  int noise_octaves = 3;          ///< 1..16
  double ring_amplitude = 0.3;    ///< wood only, in [0, 1]
  double ring_count = 8.0;        ///< rings between the axis and R, > 0
  double ring_wobble = 0.15;      ///< noise displacement of the rings, in ring widths, >= 0
};

/// `brick` (the paper's wall): running-bond brickwork, courses stacked along +y, bricks running
/// along +x, the first brick's corner at object_min; joints of mortar between bricks. Bricks
/// and mortar are both strong; the strength dips over a band around every brick–mortar
/// interface (the fracture follows the boundary):
///   w = (1 - (d/band)²)² for d < band else 0   (d: distance to the nearest brick surface),
///   ζ = clamp((1-w)·(inside a brick ? brick_strength : mortar_strength) + w·interface_strength
///       + noise_amplitude·noise(q), 0, 1).
/// Range: [max(0, min(interface, brick, mortar) - a_n·1.0364), min(1, max(...) + a_n·1.0364)];
/// [0.048, 0.952] with the defaults.
struct BrickParams {
  glm::dvec3 brick_size{0.12, 0.04, 0.0};  ///< length (x), height (y), depth (z), fractions of
                                           ///< the diagonal; depth 0 = through the whole thickness
  double mortar = 0.012;        ///< joint thickness (fraction of diagonal), > 0
  double bond_offset = 0.5;     ///< x shift of each course, in brick pitches (L + mortar)
  double brick_strength = 0.9;  ///< in [0, 1]
  double mortar_strength = 0.75;     ///< in [0, 1]
  double interface_strength = 0.1;   ///< the dip, in [0, 1]
  double band = 0.006;          ///< half-width of the dip (fraction of diagonal), > 0
  double noise_amplitude = 0.05;     ///< in [0, 1]
};

/// `inclusions` (the paper's Jell-O with fruit): a soft matrix holding `count` hard cubes at
/// seeded random positions (each cube fully inside the box where it fits), edge lengths uniform
/// in [size_min, size_max] and, if `rotate`, uniformly random orientations. Cubes may overlap.
///   w = smoothstep(edge, -edge, signed distance to the nearest cube),
///   ζ = clamp((1-w)·matrix_strength + w·inclusion_strength + noise_amplitude·noise(q), 0, 1).
/// Range: like brick's; [0.096, 1] with the defaults.
struct InclusionParams {
  int count = 12;               ///< 0..10000
  double size_min = 0.06;       ///< cube edge (fraction of diagonal), > 0
  double size_max = 0.14;       ///< >= size_min
  bool rotate = true;
  double matrix_strength = 0.2;     ///< in [0, 1]
  double inclusion_strength = 0.9;  ///< in [0, 1]
  double edge = 0.005;          ///< half-width of the jelly/cube blend (fraction of diagonal), > 0
  double noise_amplitude = 0.1;     ///< in [0, 1]
};

/// What a scene's `field` asks for. `type` is one of field_type_names():
///  - "constant": ζ ≡ value (a test material for the flow).
///  - "perlin": ζ = clamp(0.5 + 0.5·fbm.contrast·noise(q), 0, 1) in [0, 1].
///  - "fbm": ζ = clamp(0.5 + 0.5·fbm.contrast·fbm(q, fbm.octaves, fbm.lacunarity, fbm.gain), 0, 1)
///    in [0, 1]. With contrast 1 most values fall in [0.2, 0.8].
///  - "marble", "wood", "branch", "brick", "inclusions": see their parameter structs.
struct FieldSpec {
  std::string type = "constant";
  std::uint64_t seed = 1;  ///< permutation of the noise, offset o(seed), cube placement
  double scale = 0.0;      ///< noise feature size (one lattice cell), fraction of the diagonal,
                           ///< >= 0; 0 = the type's default, see effective_scale()
  double value = 1.0;      ///< "constant" only; finite
  FbmParams fbm;
  MarbleParams marble;
  WoodParams wood;  ///< "wood" and "branch"
  BrickParams brick;
  InclusionParams inclusions;
  /// The object's bounding box in material space (scene units): the frame of every material
  /// (diagonal, centre, axis, brick origin, cube placement). Unset when min > max (the
  /// default): sample_strength() then uses its own box; strength_at() requires it set.
  glm::dvec3 object_min{1.0};
  glm::dvec3 object_max{0.0};
};

/// The known field types, in a fixed order (for error messages and the CLI).
const std::vector<std::string>& field_type_names();

/// spec.scale, or when it is 0 the type's default: perlin, fbm, constant 0.25; marble 0.2;
/// wood, branch 0.1 (across the axis; along it, elongation times more); brick 0.05;
/// inclusions 0.1. Unknown types: 0.25.
double effective_scale(const FieldSpec& spec);

/// Checks the type and every parameter the type uses.
/// \throw InputError naming the parameter and the bad value, e.g.
///        "field params: 'marble.edge' must be > 0 (got -1)" or
///        "field: unknown type 'granite' (known: constant, perlin, ...)".
void validate_field_spec(const FieldSpec& spec);

/// ζ at one material-space point (scene units); builds the material each call, so prefer
/// sample_strength() for many points.
/// \pre `noise` is PerlinNoise(spec.seed) (another table gives another, equally valid field).
/// \throw InputError as validate_field_spec(), or when spec.object_min/max is unset or invalid.
double strength_at(const FieldSpec& spec, const PerlinNoise& noise, glm::dvec3 p_material);

/// Samples ζ at the nodes of a regular grid covering [bbox_min, bbox_max].
/// The grid has `resolution` nodes per axis and ONE cell size: cell = max over axes of
/// extent_a / (n_a - 1) (axes with n_a = 1 skipped; if all are 1, cell = the largest extent, or 1
/// for a point box). Along the axis attaining that maximum the nodes span bbox_min..bbox_max
/// exactly; along the others the node span (n_a - 1)·cell >= extent_a is centred on the box, so
/// origin_a = centre_a - cell·(n_a - 1)/2 (equal to bbox_min_a on the maximal axis).
/// The material frame is spec.object_min/max, or [bbox_min, bbox_max] when that is unset.
/// Runs on `threads` threads (0 = default_threads()); each node is computed independently, so the result is
/// bit-identical for any thread count.
/// \throw InputError for a zero resolution component, a non-finite or inverted box, more than
///        2^31 nodes, or a spec rejected by validate_field_spec().
Grid3 sample_strength(const FieldSpec& spec, glm::dvec3 bbox_min, glm::dvec3 bbox_max,
                      glm::uvec3 resolution, unsigned threads = 0);

/// The material's own colours at the nodes of `like` (its dims, origin and cell; its values are
/// not read), one grid per linear RGB channel in [0, 1], for pictures of the pieces: marble white
/// with blue veins (their grains shaded); wood and branch dark heartwood to pale sapwood as ζ
/// rises; inclusions red jelly with each cube a fruit of its own colour. None for the types
/// without colours of their own (constant, perlin, fbm, brick). Bit-identical for any thread count.
/// \pre spec.object_min/max set. \throw InputError as strength_at().
std::optional<std::array<Grid3, 3>> sample_albedo(const FieldSpec& spec, const Grid3& like, unsigned threads = 0);

/// One cube of an `inclusions` material (scene units).
struct InclusionCube {
  glm::dvec3 centre{0.0};
  double half_size = 0.0;
  glm::dmat3 rotation{1.0};  ///< local → material space (columns: the cube's axes)
};

/// The cubes of an `inclusions` spec, in generation order (for previews and tests).
/// \pre spec.object_min/max set. \throw InputError as strength_at().
std::vector<InclusionCube> inclusion_cubes(const FieldSpec& spec);

/// The blue-vein weight w in [0, 1] of a `marble` spec at p (1 = blue, 0 = white).
/// \pre as strength_at(). \throw InputError as strength_at().
double marble_blue_weight(const FieldSpec& spec, const PerlinNoise& noise, glm::dvec3 p_material);

}  // namespace fracref
