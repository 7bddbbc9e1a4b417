// Procedural strength fields: documented ranges, the qualitative properties the paper's scenes
// rely on, grid placement, determinism and errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "field/procedural.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

FieldSpec make_spec(const std::string& type, glm::dvec3 lo, glm::dvec3 hi) {
  FieldSpec spec;
  spec.type = type;
  spec.object_min = lo;
  spec.object_max = hi;
  return spec;
}

struct Stats {
  double lo = 1e300, hi = -1e300, mean = 0;
};

Stats stats_of(const Grid3& g) {
  Stats s;
  for (float v : g.values) {
    s.lo = std::min<double>(s.lo, v);
    s.hi = std::max<double>(s.hi, v);
    s.mean += v;
  }
  s.mean /= double(g.values.size());
  return s;
}

// The documented ranges of every type with default parameters (procedural.hpp).
struct RangeCase {
  const char* type;
  double lo, hi;
};
const RangeCase kRanges[] = {
    {"constant", 1.0, 1.0},       {"perlin", 0.0, 1.0},        {"fbm", 0.0, 1.0},
    {"marble", 0.05, 1.0},        {"branch", 0.0, 1.0},        {"wood", 0.0, 1.0},
    {"brick", 0.1 - 0.05 * kPerlinNoiseBound, 0.9 + 0.05 * kPerlinNoiseBound},
    {"inclusions", 0.2 - 0.1 * kPerlinNoiseBound, 1.0},
};

TEST(ProceduralField, EveryTypeStaysWithinItsDocumentedRange) {
  const glm::dvec3 lo{-1.0, -0.5, -2.0}, hi{1.0, 0.5, 2.0};
  ASSERT_EQ(field_type_names().size(), std::size(kRanges));
  for (const RangeCase& c : kRanges) {
    const Grid3 g = sample_strength(make_spec(c.type, lo, hi), lo, hi, {24, 12, 48});
    const Stats s = stats_of(g);
    EXPECT_GE(s.lo, c.lo - 1e-6) << c.type;
    EXPECT_LE(s.hi, c.hi + 1e-6) << c.type;
    if (std::string(c.type) != "constant") {
      EXPECT_GT(s.hi - s.lo, 0.3) << c.type << ": too flat";
    }
  }
}

TEST(ProceduralField, ConstantIsItsValue) {
  FieldSpec spec = make_spec("constant", {0, 0, 0}, {1, 1, 1});
  spec.value = 0.375;
  const Grid3 g = sample_strength(spec, {0, 0, 0}, {1, 1, 1}, {4, 4, 4});
  for (float v : g.values) EXPECT_EQ(v, 0.375f);
}

// Mean strength of grid nodes whose radial distance to the z axis lies in [r0, r1).
double mean_in_shell(const Grid3& g, double r0, double r1) {
  double sum = 0;
  int n = 0;
  for (unsigned z = 0; z < g.dims.z; ++z)
    for (unsigned y = 0; y < g.dims.y; ++y)
      for (unsigned x = 0; x < g.dims.x; ++x) {
        const glm::dvec3 p = g.node_position(x, y, z);
        const double r = std::hypot(p.x, p.y);
        if (r >= r0 && r < r1) sum += g.at(x, y, z), ++n;
      }
  EXPECT_GT(n, 100);
  return sum / n;
}

TEST(ProceduralField, BranchAndWoodAreSoftNearTheAxisAndHardNearTheSurface) {
  // A unit-radius cylinder's box, axis z through the centre: the default axis and radius.
  const glm::dvec3 lo{-1, -1, -4}, hi{1, 1, 4};
  for (const char* type : {"branch", "wood"}) {
    const Grid3 g = sample_strength(make_spec(type, lo, hi), lo, hi, {32, 32, 64});
    const double core = mean_in_shell(g, 0.0, 0.3), surface = mean_in_shell(g, 0.8, 1.0);
    EXPECT_LT(core + 0.15, surface) << type << " core " << core << " surface " << surface;
  }
}

// Mean |ζ(p + h·dir) - ζ(p)| over points of the box interior.
double mean_variation(const FieldSpec& spec, const PerlinNoise& noise, glm::dvec3 dir, double h) {
  std::uint64_t s = 77;
  double sum = 0;
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 p{(double(splitmix64(s) >> 11) * 0x1.0p-53 - 0.5) * 1.2,
                       (double(splitmix64(s) >> 11) * 0x1.0p-53 - 0.5) * 1.2,
                       (double(splitmix64(s) >> 11) * 0x1.0p-53 - 0.5) * 6.0};
    sum += std::abs(strength_at(spec, noise, p + h * dir) - strength_at(spec, noise, p));
  }
  return sum / n;
}

TEST(ProceduralField, BranchNoiseIsElongatedAlongTheAxis) {
  FieldSpec spec = make_spec("branch", {-1, -1, -4}, {1, 1, 4});
  spec.wood.core_strength = spec.wood.surface_strength = 0.5;  // only the noise varies
  const PerlinNoise noise(spec.seed);
  const double along = mean_variation(spec, noise, {0, 0, 1}, 0.2);
  const double across = mean_variation(spec, noise, {1, 0, 0}, 0.2);
  EXPECT_LT(along * 3.0, across) << "along " << along << " across " << across;
}

TEST(ProceduralField, BrickIsWeakAtTheBrickMortarInterface) {
  const glm::dvec3 lo{0, 0, 0}, hi{3, 1, 0.2};
  FieldSpec spec = make_spec("brick", lo, hi);
  const double d = glm::length(hi - lo);
  const double L = 0.12 * d, H = 0.04 * d, m = 0.012 * d;
  const PerlinNoise noise(spec.seed);
  double interface_sum = 0, brick_sum = 0, mortar_sum = 0;
  int n = 0;
  for (int j = 1; j <= 4; ++j)
    for (int i = 1; i <= 4; ++i, ++n) {
      // Brick (i, j) of the running bond: course j shifted by half a pitch per course.
      const double x0 = i * (L + m) + j * 0.5 * (L + m), y0 = j * (H + m);
      const glm::dvec3 centre{x0 + L / 2, y0 + H / 2, 0.1};
      const glm::dvec3 top{x0 + L / 2, y0 + H, 0.1}, side{x0 + L, y0 + H / 3, 0.05};
      const glm::dvec3 bed{x0 + L / 3, y0 + H + m / 2, 0.1}, head{x0 + L + m / 2, y0 + H / 2, 0.1};
      const double z_top = strength_at(spec, noise, top), z_side = strength_at(spec, noise, side);
      const double z_centre = strength_at(spec, noise, centre);
      const double z_bed = strength_at(spec, noise, bed), z_head = strength_at(spec, noise, head);
      EXPECT_LT(z_top, z_centre);
      EXPECT_LT(z_side, z_centre);
      EXPECT_LT(z_top, z_bed);
      EXPECT_LT(z_side, z_head);
      interface_sum += z_top + z_side;
      brick_sum += 2 * z_centre;
      mortar_sum += z_bed + z_head;
    }
  EXPECT_LT(interface_sum / (2 * n), 0.2);
  EXPECT_GT(brick_sum / (2 * n), 0.8);
  EXPECT_GT(mortar_sum / (2 * n), 0.65);

  // Without noise the three regions take exactly their parameters.
  spec.brick.noise_amplitude = 0.0;
  const double x0 = 2 * (L + m) + 0.5 * (L + m), y0 = H + m;
  EXPECT_DOUBLE_EQ(strength_at(spec, noise, {x0 + L / 2, y0 + H, 0.1}), 0.1);
  EXPECT_DOUBLE_EQ(strength_at(spec, noise, {x0 + L / 2, y0 + H / 2, 0.1}), 0.9);
  EXPECT_DOUBLE_EQ(strength_at(spec, noise, {x0 + L + m / 2, y0 + H / 2, 0.1}), 0.75);
  // Layers along z when a depth is given: its faces are interfaces too.
  spec.brick.brick_size.z = 0.03;
  const double D = 0.03 * d;
  EXPECT_DOUBLE_EQ(strength_at(spec, noise, {x0 + L / 2, y0 + H / 2, D}), 0.1);
  EXPECT_DOUBLE_EQ(strength_at(spec, noise, {x0 + L / 2, y0 + H / 2, D / 2}), 0.9);
}

TEST(ProceduralField, InclusionCubesAreHarderThanTheJelly) {
  const glm::dvec3 lo{-1, -1, -0.5}, hi{1, 1, 0.5};
  const FieldSpec spec = make_spec("inclusions", lo, hi);
  const auto cubes = inclusion_cubes(spec);
  ASSERT_EQ(cubes.size(), 12u);
  const PerlinNoise noise(spec.seed);
  double inside = 0;
  for (const InclusionCube& c : cubes) {
    // Fully inside the box: every corner.
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner = c.centre + c.rotation * (c.half_size * glm::dvec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(corner, lo)) && glm::all(glm::lessThanEqual(corner, hi)));
    }
    EXPECT_NEAR(glm::determinant(c.rotation), 1.0, 1e-12);
    inside += strength_at(spec, noise, c.centre) / double(cubes.size());
  }
  // Outside: grid nodes farther than the blend band from every cube's bounding sphere.
  const Grid3 g = sample_strength(spec, lo, hi, {20, 20, 10});
  double outside = 0;
  int n = 0;
  for (unsigned i = 0; i < g.values.size(); ++i) {
    const glm::dvec3 p = g.node_position(i % 20, (i / 20) % 20, i / 400);
    const bool clear = std::all_of(cubes.begin(), cubes.end(), [&](const InclusionCube& c) {
      return glm::length(p - c.centre) > c.half_size * 1.7321 + 0.006 * glm::length(hi - lo);
    });
    if (clear) outside += g.values[i], ++n;
  }
  ASSERT_GT(n, 100);
  outside /= n;
  EXPECT_GT(inside, 0.75);
  EXPECT_LT(outside, 0.35);
  EXPECT_GT(inside, outside + 0.4);

  FieldSpec other = spec;
  other.seed = 2;
  EXPECT_NE(inclusion_cubes(other)[0].centre, cubes[0].centre);
  EXPECT_EQ(inclusion_cubes(spec)[5].centre, cubes[5].centre);
}

TEST(ProceduralField, MarbleBlueVeinsAreHarderAndFinerGrainedThanWhite) {
  const glm::dvec3 lo{-1, -1, -1}, hi{1, 1, 1};
  const FieldSpec spec = make_spec("marble", lo, hi);
  const PerlinNoise noise(spec.seed);
  const Grid3 g = sample_strength(spec, lo, hi, {40, 40, 40});
  double blue = 0, white = 0, blue_step = 0, white_step = 0;
  int nb = 0, nw = 0;
  for (unsigned z = 0; z < 40; ++z)
    for (unsigned y = 0; y < 40; ++y)
      for (unsigned x = 0; x + 1 < 40; ++x) {
        const double w0 = marble_blue_weight(spec, noise, g.node_position(x, y, z));
        const double w1 = marble_blue_weight(spec, noise, g.node_position(x + 1, y, z));
        const double step = std::abs(g.at(x + 1, y, z) - g.at(x, y, z));
        if (w0 > 0.999 && w1 > 0.999) blue += g.at(x, y, z), blue_step += step, ++nb;
        if (w0 < 0.001 && w1 < 0.001) white += g.at(x, y, z), white_step += step, ++nw;
      }
  const double total = 40.0 * 40 * 39;
  EXPECT_GT(nb / total, 0.1);
  EXPECT_GT(nw / total, 0.3);
  EXPECT_GT(blue / nb, white / nw + 0.3);
  // Blue: fine grains (high frequency), white: smooth (low frequency).
  EXPECT_GT(blue_step / nb, 2.0 * (white_step / nw));
}

TEST(ProceduralField, SameSpecOnAScaledAndMovedObjectGivesTheSameField) {
  const glm::dvec3 lo{-1, -0.5, -2}, hi{1, 0.5, 2}, shift{10, -3, 7};
  std::uint64_t s = 4;
  for (const std::string& type : field_type_names()) {
    const FieldSpec a = make_spec(type, lo, hi), b = make_spec(type, 10.0 * lo + shift, 10.0 * hi + shift);
    const PerlinNoise noise(a.seed);
    for (int i = 0; i < 200; ++i) {
      const glm::dvec3 u{double(splitmix64(s) >> 11) * 0x1.0p-53, double(splitmix64(s) >> 11) * 0x1.0p-53,
                         double(splitmix64(s) >> 11) * 0x1.0p-53};
      const glm::dvec3 p = lo + u * (hi - lo);
      ASSERT_NEAR(strength_at(a, noise, p), strength_at(b, noise, 10.0 * p + shift), 1e-6) << type;
    }
  }
}

TEST(SampleStrength, GridPlacementIsExact) {
  const FieldSpec spec = make_spec("constant", {0, 0, 0}, {1, 1, 1});
  // Extents 2, 2, 1 over 5, 9, 3 nodes: x and z need cell 0.5, y only 0.25, so y is centred.
  const Grid3 g = sample_strength(spec, {0, 1, -1}, {2, 3, 0}, {5, 9, 3});
  EXPECT_EQ(g.dims, glm::uvec3(5, 9, 3));
  EXPECT_EQ(g.cell, 0.5);
  EXPECT_EQ(g.origin, glm::dvec3(0.0, 0.0, -1.0));
  EXPECT_EQ(g.values.size(), 5u * 9u * 3u);
  EXPECT_EQ(g.node_position(4, 0, 2).x, 2.0);
  EXPECT_EQ(g.node_position(4, 0, 2).z, 0.0);
  EXPECT_EQ(g.node_position(0, 8, 0).y, 4.0);  // centred on y's [1, 3]: spans [0, 4]

  const Grid3 one = sample_strength(spec, {0, 1, -1}, {2, 3, 0}, {1, 1, 1});
  EXPECT_EQ(one.cell, 2.0);
  EXPECT_EQ(one.origin, glm::dvec3(1.0, 2.0, -0.5));

  const Grid3 irregular = sample_strength(spec, {0.1, 0.2, 0.3}, {1.7, 0.9, 0.35}, {17, 8, 2});
  EXPECT_EQ(irregular.origin.x, 0.1);
  EXPECT_NEAR(irregular.node_position(16, 0, 0).x, 1.7, 1e-15);
  EXPECT_NEAR(irregular.cell, 0.1, 1e-16);
  EXPECT_NEAR(irregular.origin.y + 3.5 * irregular.cell, 0.55, 1e-15);
}

TEST(SampleStrength, NodesHoldStrengthAtTheirPositions) {
  const glm::dvec3 lo{-1, -0.5, 0}, hi{1, 0.5, 0.7};
  for (const std::string& type : field_type_names()) {
    FieldSpec unset = make_spec(type, {1, 1, 1}, {0, 0, 0});  // frame taken from the grid box
    const Grid3 g = sample_strength(unset, lo, hi, {9, 5, 4});
    const FieldSpec set = make_spec(type, lo, hi);
    const PerlinNoise noise(set.seed);
    for (unsigned z = 0; z < 4; ++z)
      for (unsigned x = 0; x < 9; ++x)
        ASSERT_EQ(g.at(x, 2, z), static_cast<float>(strength_at(set, noise, g.node_position(x, 2, z))))
            << type;
  }
}

TEST(SampleStrength, BitIdenticalForAnyThreadCount) {
  const glm::dvec3 lo{-1, -0.5, -0.25}, hi{1, 0.5, 0.25};
  for (const char* type : {"marble", "inclusions", "brick", "wood"}) {
    const FieldSpec spec = make_spec(type, lo, hi);
    const Grid3 one = sample_strength(spec, lo, hi, {40, 20, 11}, 1);
    const Grid3 two = sample_strength(spec, lo, hi, {40, 20, 11}, 2);
    const Grid3 many = sample_strength(spec, lo, hi, {40, 20, 11}, 5);
    ASSERT_EQ(one.values.size(), two.values.size());
    EXPECT_EQ(std::memcmp(one.values.data(), two.values.data(), one.values.size() * sizeof(float)), 0) << type;
    EXPECT_EQ(std::memcmp(one.values.data(), many.values.data(), one.values.size() * sizeof(float)), 0) << type;
  }
}

TEST(SampleStrength, SeedsAreDeterministicAndDistinct) {
  const glm::dvec3 lo{0, 0, 0}, hi{1, 1, 1};
  for (const char* type : {"perlin", "fbm", "marble", "branch", "inclusions"}) {
    FieldSpec spec = make_spec(type, lo, hi);
    const Grid3 a = sample_strength(spec, lo, hi, {12, 12, 12});
    const Grid3 b = sample_strength(spec, lo, hi, {12, 12, 12});
    spec.seed = 99;
    const Grid3 c = sample_strength(spec, lo, hi, {12, 12, 12});
    EXPECT_EQ(a.values, b.values) << type;
    EXPECT_NE(a.values, c.values) << type;
  }
}

TEST(SampleStrength, BadInputThrowsInputErrorNamingTheCause) {
  const glm::dvec3 lo{0, 0, 0}, hi{1, 1, 1};
  FieldSpec spec = make_spec("granite", lo, hi);
  try {
    sample_strength(spec, lo, hi, {4, 4, 4});
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown type 'granite'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("inclusions"), std::string::npos) << e.what();
  }
  spec.type = "marble";
  spec.marble.edge = -1;
  try {
    sample_strength(spec, lo, hi, {4, 4, 4});
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'marble.edge' must be > 0 (got -1)"), std::string::npos) << e.what();
  }
  spec.marble.edge = 0.1;
  spec.scale = -1;
  EXPECT_THROW(sample_strength(spec, lo, hi, {4, 4, 4}), InputError);
  spec.scale = 0.25;
  spec.type = "wood";
  spec.wood.ring_amplitude = 1.5;
  EXPECT_THROW(sample_strength(spec, lo, hi, {4, 4, 4}), InputError);
  spec.type = "branch";  // branch ignores the rings
  EXPECT_NO_THROW(sample_strength(spec, lo, hi, {4, 4, 4}));

  EXPECT_THROW(sample_strength(spec, lo, hi, {4, 0, 4}), InputError);
  EXPECT_THROW(sample_strength(spec, hi, lo, {4, 4, 4}), InputError);
  EXPECT_THROW(sample_strength(spec, lo, {1, NAN, 1}, {4, 4, 4}), InputError);
  EXPECT_THROW(sample_strength(spec, lo, lo, {4, 4, 4}), InputError);
  FieldSpec unset;
  unset.type = "perlin";
  EXPECT_THROW(strength_at(unset, PerlinNoise(1), {0, 0, 0}), InputError);
}

// Every material samples a full 64^3 grid (its speed is measured in bench/field_bench.cpp).
TEST(SampleStrength, Samples64CubedForEveryMaterial) {
  const glm::dvec3 lo{-1, -1, -1}, hi{1, 1, 1};
  for (const std::string& type : field_type_names()) {
    const Grid3 g = sample_strength(make_spec(type, lo, hi), lo, hi, {64, 64, 64}, 1);
    EXPECT_EQ(g.values.size(), 64u * 64u * 64u);
  }
}

}  // namespace
}  // namespace fracref
