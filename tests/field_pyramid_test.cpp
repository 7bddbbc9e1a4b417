// The CPU Gaussian pyramid: its definition, its geometry and its invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "field/field_sampler.hpp"
#include "field/pyramid.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

Grid3 random_grid(glm::uvec3 dims, unsigned seed) {
  Grid3 g;
  g.dims = dims;
  g.origin = glm::dvec3(-1.5, 0.25, 3.0);
  g.cell = 0.1;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  g.values.resize(g.size());
  for (float& v : g.values) v = u(rng);
  return g;
}

Grid3 constant_grid(glm::uvec3 dims, float value) {
  Grid3 g;
  g.dims = dims;
  g.values.assign(g.size(), value);
  return g;
}

// The definition, written independently of the pyramid code: keep every second node.
Grid3 downsample2(const Grid3& g) {
  Grid3 out;
  out.dims = (g.dims + 1u) / 2u;
  out.origin = g.origin;
  out.cell = 2.0 * g.cell;
  out.values.resize(out.size());
  for (unsigned z = 0; z < out.dims.z; ++z)
    for (unsigned y = 0; y < out.dims.y; ++y)
      for (unsigned x = 0; x < out.dims.x; ++x) out.values[out.index(x, y, z)] = g.at(2 * x, 2 * y, 2 * z);
  return out;
}

double sum(const std::vector<float>& v) {
  double s = 0.0;
  for (float x : v) s += x;
  return s;
}

TEST(GaussianWeights, NormalisedSymmetricGaussian) {
  const std::vector<float> w = gaussian_weights(1.0f);
  ASSERT_EQ(w.size(), 7u);  // r = ceil(3 sigma) = 3
  EXPECT_NEAR(sum(w), 1.0, 1e-6);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(w[k], w[6 - k]);
  EXPECT_NEAR(w[4] / w[3], std::exp(-0.5), 1e-6);
  EXPECT_NEAR(w[5] / w[3], std::exp(-2.0), 1e-6);
  EXPECT_EQ(gaussian_weights(0.5f).size(), 5u);
  EXPECT_EQ(gaussian_weights(2.0f).size(), 13u);
  EXPECT_EQ(gaussian_weights(0.1f).size(), 3u);
}

TEST(Pyramid, LevelGeometryIsExact) {
  Grid3 base = random_grid({17, 9, 5}, 1);
  const auto levels = build_pyramid_cpu(base, {.levels = 6});
  const glm::uvec3 expected[] = {{17, 9, 5}, {9, 5, 3}, {5, 3, 2}, {3, 2, 1}, {2, 1, 1}, {1, 1, 1}};
  ASSERT_EQ(levels.size(), 6u);
  for (int l = 0; l < 6; ++l) {
    SCOPED_TRACE(l);
    EXPECT_EQ(levels[l].dims, expected[l]);
    EXPECT_EQ(levels[l].values.size(), levels[l].size());
    EXPECT_EQ(levels[l].origin, base.origin);
    EXPECT_EQ(levels[l].cell, base.cell * double(1 << l));
  }
  EXPECT_EQ(levels[0].values, base.values);
  EXPECT_EQ(pyramid_level_dims({17, 9, 5}, 6).back(), glm::uvec3(1, 1, 1));
}

TEST(Pyramid, ConstantGridStaysConstant) {
  const auto levels = build_pyramid_cpu(constant_grid({17, 9, 5}, 3.25f), {.levels = 5});
  for (const Grid3& level : levels)
    for (float v : level.values) EXPECT_NEAR(v, 3.25f, 3.25f * 1e-6f);
}

TEST(Pyramid, DeltaBlursToNormalisedGaussian) {
  Grid3 delta = constant_grid({15, 15, 15}, 0.0f);
  delta.values[delta.index(7, 7, 7)] = 1.0f;
  const Grid3 blurred = blur_cpu(delta, 1.0f);
  const std::vector<float> w = gaussian_weights(1.0f);
  auto g = [](int k) { return std::exp(-0.5 * k * k); };
  double norm = 0.0;
  for (int k = -3; k <= 3; ++k) norm += g(k);
  for (unsigned z = 0; z < 15; ++z)
    for (unsigned y = 0; y < 15; ++y)
      for (unsigned x = 0; x < 15; ++x) {
        const int dx = int(x) - 7, dy = int(y) - 7, dz = int(z) - 7;
        const bool inside = std::abs(dx) <= 3 && std::abs(dy) <= 3 && std::abs(dz) <= 3;
        const double expected = inside ? g(dx) * g(dy) * g(dz) / (norm * norm * norm) : 0.0;
        ASSERT_NEAR(blurred.at(x, y, z), expected, 1e-7) << x << "," << y << "," << z;
      }
  EXPECT_NEAR(sum(blurred.values), 1.0, 1e-6);
}

TEST(Pyramid, EveryLevelIsTheDownsampledBlurOfTheOneBelow) {
  for (glm::uvec3 dims : {glm::uvec3(17, 9, 5), glm::uvec3(32, 32, 32), glm::uvec3(1, 6, 2)}) {
    const Grid3 base = random_grid(dims, dims.x);
    const auto levels = build_pyramid_cpu(base, {.levels = 5, .sigma = 1.3f});
    for (int l = 0; l + 1 < 5; ++l) {
      const Grid3 expected = downsample2(blur_cpu(levels[l], 1.3f));
      ASSERT_EQ(levels[l + 1].dims, expected.dims);
      // Bit for bit: the pyramid computes the kept nodes with the very same operations.
      EXPECT_EQ(0, std::memcmp(levels[l + 1].values.data(), expected.values.data(),
                               expected.values.size() * sizeof(float)))
          << "level " << l + 1;
    }
  }
}

TEST(Pyramid, BlurPreservesTheSumAwayFromBorders) {
  Grid3 g = random_grid({24, 20, 16}, 7);
  const int r = 3;
  for (unsigned z = 0; z < g.dims.z; ++z)
    for (unsigned y = 0; y < g.dims.y; ++y)
      for (unsigned x = 0; x < g.dims.x; ++x) {
        const bool interior = x >= unsigned(r) && x + r < g.dims.x && y >= unsigned(r) && y + r < g.dims.y &&
                              z >= unsigned(r) && z + r < g.dims.z;
        if (!interior) g.values[g.index(x, y, z)] = 0.0f;
        else g.values[g.index(x, y, z)] += 2.0f;  // a sum far from zero, so the check is relative
      }
  const double before = sum(g.values);
  EXPECT_NEAR(sum(blur_cpu(g, 1.0f).values), before, 1e-5 * before);
  // A signal touching the border leaks through the clamp: the check above can fail.
  g.values[0] = 100.0f;
  EXPECT_GT(std::abs(sum(blur_cpu(g, 1.0f).values) - sum(g.values)), 1.0);
}

TEST(Pyramid, AnyThreadCountIsBitIdentical) {
  const Grid3 base = random_grid({50, 50, 50}, 3);
  const auto one = build_pyramid_cpu(base, {.levels = 6, .threads = 1});
  const auto two = build_pyramid_cpu(base, {.levels = 6, .threads = 2});
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t l = 0; l < one.size(); ++l) {
    ASSERT_EQ(one[l].values.size(), two[l].values.size());
    EXPECT_EQ(0, std::memcmp(one[l].values.data(), two[l].values.data(), one[l].values.size() * sizeof(float)));
  }
  const auto five = build_pyramid_cpu(base, {.levels = 6, .threads = 5});
  for (std::size_t l = 0; l < one.size(); ++l)
    EXPECT_EQ(0, std::memcmp(one[l].values.data(), five[l].values.data(), one[l].values.size() * sizeof(float)));
  const Grid3 b1 = blur_cpu(base, 1.0f, 1), b2 = blur_cpu(base, 1.0f, 2), b7 = blur_cpu(base, 1.0f, 7);
  EXPECT_EQ(0, std::memcmp(b1.values.data(), b2.values.data(), b1.values.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(b1.values.data(), b7.values.data(), b1.values.size() * sizeof(float)));
}

// Trilinear interpolation of `level` at level coordinate c (in cells from its origin), clamped
// into the level, as sample_trilinear sums it: the eight terms in the same order.
double trilinear_at(const Grid3& level, const glm::dvec3& c) {
  unsigned i[3][2];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const unsigned n = level.dims[a];
    const double x = std::clamp(c[a], 0.0, double(n - 1));
    const unsigned i0 = n >= 2 ? std::min<unsigned>(unsigned(std::floor(x)), n - 2) : 0;
    i[a][0] = i0, i[a][1] = n >= 2 ? i0 + 1 : 0, t[a] = n >= 2 ? x - i0 : 0.0;
  }
  double acc = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int bx = k & 1, by = (k >> 1) & 1, bz = (k >> 2) & 1;
    const double w = (bx ? t[0] : 1 - t[0]) * (by ? t[1] : 1 - t[1]) * (bz ? t[2] : 1 - t[2]);
    acc += w * level.at(i[0][bx], i[1][by], i[2][bz]);
  }
  return acc;
}

// precompute_field_gradient against its documented definition, evaluated point by point: the
// value at base node k is the mean over the levels of level l's trilinear interpolation at level
// coordinate k / 2^l; the gradient is the central difference of those values one base cell either
// side (one-sided at the grid's faces). The same doubles in the same order, so the floats must be
// equal (levels with odd dims, a coarse level of 2 nodes on one axis).
TEST(FieldGradient, IsTheCentralDifferenceOfTheMeanOfTheLevels) {
  PyramidOptions po;
  po.levels = 4;
  Grid3 g = random_grid({13, 9, 16}, 5);
  g.origin = glm::dvec3(0.3, -1.7, 2.9);  // world positions that round: the index space must not
  g.cell = 0.1;
  const std::vector<Grid3> pyramid = build_pyramid_cpu(g, po);
  const FieldGrid4 f = precompute_field_gradient(pyramid);
  const Grid3& base = pyramid.front();
  ASSERT_EQ(f.values.size(), base.size());
  auto mean = [&](glm::ivec3 k) {
    double value = 0.0;
    for (std::size_t l = 0; l < pyramid.size(); ++l) value += trilinear_at(pyramid[l], glm::dvec3(k) / double(1u << l));
    return value / double(pyramid.size());
  };
  const glm::ivec3 n(base.dims);
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        const glm::ivec3 k(x, y, z);
        glm::dvec3 grad(0.0);
        for (int a = 0; a < 3; ++a) {
          glm::ivec3 lo = k, hi = k;
          lo[a] = std::max(k[a] - 1, 0), hi[a] = std::min(k[a] + 1, n[a] - 1);
          grad[a] = (mean(hi) - mean(lo)) / (double(hi[a] - lo[a]) * base.cell);
        }
        const glm::vec4 want(float(mean(k)), glm::vec3(grad));
        ASSERT_EQ(f.values[base.index(x, y, z)], want) << "node " << x << " " << y << " " << z;
      }
}

// What the flow needs: the gradient channel is the derivative of the value channel the refiner
// samples (sample_field), so a step along −∇ψ lowers the energy it measures. The coarse levels'
// own central differences (a level cell either side) are not: on a field that changes within a
// coarse cell they differ from the interpolated values' slope by a large fraction, and the flow
// stalled on the branch demo. Checked between interior nodes, where trilinear interpolation is
// linear along an axis.
TEST(FieldGradient, IsTheSlopeOfTheSampledValue) {
  PyramidOptions po;
  po.levels = 5;
  Grid3 g = random_grid({20, 17, 33}, 11);
  g.origin = glm::dvec3(-0.37, 1.21, 0.05);
  g.cell = 0.0731;
  const FieldGrid4 f = precompute_field_gradient(build_pyramid_cpu(g, po));
  for (unsigned z = 1; z + 1 < g.dims.z; z += 3)
    for (unsigned y = 1; y + 1 < g.dims.y; y += 2)
      for (unsigned x = 1; x + 1 < g.dims.x; x += 2) {
        const glm::vec3 p(g.node_position(x, y, z));
        const glm::vec4 at = sample_field(f, p);
        for (int a = 0; a < 3; ++a) {
          glm::vec3 e(0.0f);
          e[a] = float(g.cell);
          const double slope = (double(sample_field(f, p + e).x) - sample_field(f, p - e).x) / (2.0 * g.cell);
          EXPECT_NEAR(at[a + 1], slope, 1e-3 * (1.0 + std::abs(slope))) << x << " " << y << " " << z << " axis " << a;
        }
      }
}

// The index-space sampling needs levels laid out as the pyramid builds them: anything else is
// refused, not sampled wrongly.
TEST(FieldGradient, RejectsLevelsNotLaidOutAsThePyramid) {
  PyramidOptions po;
  po.levels = 3;
  const std::vector<Grid3> pyramid = build_pyramid_cpu(random_grid({9, 8, 7}, 3), po);
  EXPECT_NO_THROW(precompute_field_gradient(pyramid));
  EXPECT_THROW(precompute_field_gradient({}), InputError);
  std::vector<Grid3> bad = pyramid;
  bad[1].cell *= 1.5;
  EXPECT_THROW(precompute_field_gradient(bad), InputError);
  bad = pyramid;
  bad[2].origin.x += 0.25;
  EXPECT_THROW(precompute_field_gradient(bad), InputError);
  bad = pyramid;
  bad[2] = bad[1];
  EXPECT_THROW(precompute_field_gradient(bad), InputError);
}

TEST(Pyramid, RejectsBadInput) {
  const Grid3 g = random_grid({4, 4, 4}, 1);
  EXPECT_THROW(build_pyramid_cpu(g, {.levels = 0}), InputError);
  EXPECT_THROW(build_pyramid_cpu(g, {.levels = 9}), InputError);
  EXPECT_THROW(build_pyramid_cpu(g, {.sigma = 0.0f}), InputError);
  EXPECT_THROW(build_pyramid_cpu(g, {.sigma = std::nanf("")}), InputError);
  EXPECT_THROW(build_pyramid_cpu(g, {.sigma = 100.0f}), InputError);
  EXPECT_THROW(build_pyramid_cpu(g, {.threads = 0}), InputError);
  Grid3 empty = g;
  empty.dims.y = 0;
  empty.values.clear();
  EXPECT_THROW(build_pyramid_cpu(empty, {}), InputError);
  Grid3 short_values = g;
  short_values.values.pop_back();
  EXPECT_THROW(build_pyramid_cpu(short_values, {}), InputError);
  EXPECT_NO_THROW(build_pyramid_cpu(g, {.levels = 8}));
}

}  // namespace
}  // namespace fracref
