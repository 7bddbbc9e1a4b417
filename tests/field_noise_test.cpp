// Perlin's improved noise: the reference values of his 2002 Java implementation, its
// properties, the seeded tables, and the octave sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "field/noise.hpp"

namespace fracref {
namespace {

// Deterministic uniform samples in [lo, hi) from splitmix64 (no std:: distributions).
double uniform(std::uint64_t& state, double lo, double hi) {
  return lo + (hi - lo) * (double(splitmix64(state) >> 11) * 0x1.0p-53);
}

glm::dvec3 random_point(std::uint64_t& state, double lo, double hi) {
  const double x = uniform(state, lo, hi), y = uniform(state, lo, hi), z = uniform(state, lo, hi);
  return {x, y, z};
}

TEST(PerlinNoise, ReferenceValues) {
  // Ken Perlin's ImprovedNoise.noise(3.14, 42, 7), as printed by his Java reference.
  EXPECT_NEAR(perlin_noise(3.14, 42, 7), 0.13691995878400012, 1e-15);
  // Further values of the reference algorithm, as published in ports' test suites.
  EXPECT_NEAR(perlin_noise(-4.20, 10, 6), 0.14208000000000043, 1e-15);
  EXPECT_NEAR(perlin_noise(0.5, 0.5, 0.5), -0.25, 1e-15);
  EXPECT_NEAR(perlin_noise(0.1, 0.1, 0.1), 0.1861607143544832, 1e-15);
}

TEST(PerlinNoise, ZeroAtIntegerLatticePoints) {
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y)
      for (int z = -3; z <= 3; ++z) EXPECT_EQ(perlin_noise(x, y, z), 0.0) << x << " " << y << " " << z;
  // Far outside the range of a 32-bit cast: the lattice wrap is exact.
  EXPECT_EQ(perlin_noise(1e12, -3e9, 7e15), 0.0);
}

TEST(PerlinNoise, PeriodicWithPeriod256) {
  std::uint64_t s = 11;
  for (int i = 0; i < 1000; ++i) {
    const glm::dvec3 p = random_point(s, -50.0, 50.0);
    EXPECT_NEAR(perlin_noise(p.x + 256, p.y - 512, p.z + 2560), perlin_noise(p.x, p.y, p.z), 1e-11);
  }
  // A coordinate beyond 2^31, still periodic (the Java cast would overflow there).
  EXPECT_NEAR(perlin_noise(0.25 + 1099511627776.0, 0.5, 0.75), perlin_noise(0.25, 0.5, 0.75), 1e-12);
}

TEST(PerlinNoise, RangeOnManyRandomSamples) {
  std::uint64_t s = 12345;
  double lo = 0, hi = 0, sum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 p = random_point(s, -300.0, 300.0);
    const double v = perlin_noise(p.x, p.y, p.z);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    sum += v;
  }
  EXPECT_GE(lo, -1.0);
  EXPECT_LE(hi, 1.0);
  // A meaningful spread and a mean near 0.
  EXPECT_LT(lo, -0.7);
  EXPECT_GT(hi, 0.7);
  EXPECT_NEAR(sum / n, 0.0, 0.01);
}

TEST(PerlinNoise, CanExceedOneButNotTheDocumentedBound) {
  // A local maximum of the reference table found by hill climbing: the reference noise is not
  // bounded by 1, which is why materials clamp after mapping it to [0, 1].
  const double v = perlin_noise(80.361679, 65.487580, 5.476273);
  EXPECT_GT(v, 1.02);
  EXPECT_LT(v, kPerlinNoiseBound);
}

TEST(PerlinNoise, ContinuousAndSmoothAcrossCellFaces) {
  std::uint64_t s = 5;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 p = random_point(s, -20.0, 20.0);
    const double h = 1e-7;
    EXPECT_LT(std::abs(perlin_noise(p.x + h, p.y, p.z) - perlin_noise(p.x, p.y, p.z)), 1e-5);
    EXPECT_LT(std::abs(perlin_noise(p.x, p.y, p.z + h) - perlin_noise(p.x, p.y, p.z)), 1e-5);
  }
  // Across the face x = 3: values and one-sided slopes meet (the fade curve is C2).
  const double y = 0.37, z = 0.81, e = 1e-6;
  EXPECT_NEAR(perlin_noise(3 - e, y, z), perlin_noise(3 + e, y, z), 1e-5);
  const double left = (perlin_noise(3 - e, y, z) - perlin_noise(3 - 2 * e, y, z)) / e;
  const double right = (perlin_noise(3 + 2 * e, y, z) - perlin_noise(3 + e, y, z)) / e;
  EXPECT_NEAR(left, right, 1e-3);
}

TEST(Splitmix64, MatchesTheReferenceStream) {
  // Vigna's splitmix64.c started from state 0.
  std::uint64_t state = 0;
  EXPECT_EQ(splitmix64(state), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(splitmix64(state), 0x6E789E6AA1B965F4ULL);
  EXPECT_EQ(splitmix64(state), 0x06C45D188009454FULL);
}

TEST(SeededNoise, SeedZeroIsTheReferenceTable) {
  const PerlinNoise noise(0);
  const auto perm = noise.permutation();
  EXPECT_EQ(perm[0], 151);
  EXPECT_EQ(perm[1], 160);
  EXPECT_EQ(perm[255], 180);
  std::uint64_t s = 3;
  for (int i = 0; i < 5000; ++i) {
    const glm::dvec3 p = random_point(s, -100.0, 100.0);
    ASSERT_EQ(noise(p), perlin_noise(p.x, p.y, p.z));
  }
}

TEST(SeededNoise, OtherSeedsShuffleDeterministically) {
  const PerlinNoise a(1), b(1), ref(0), c(2);
  auto perm = a.permutation();
  EXPECT_EQ(perm, b.permutation());
  EXPECT_NE(perm, ref.permutation());
  EXPECT_NE(perm, c.permutation());
  // Pinned (cross-checked by an independent Python implementation of the documented shuffle):
  // the portable shuffle must not drift between platforms or releases.
  EXPECT_EQ(perm[0], 92);
  EXPECT_EQ(perm[1], 220);
  EXPECT_EQ(perm[2], 68);
  EXPECT_EQ(perm[255], 246);
  std::sort(perm.begin(), perm.end());
  for (int i = 0; i < 256; ++i) ASSERT_EQ(perm[i], i);

  std::uint64_t s = 9;
  int differ = 0;
  for (int i = 0; i < 1000; ++i) {
    const glm::dvec3 p = random_point(s, -100.0, 100.0);
    ASSERT_EQ(a(p), b(p));
    differ += a(p) != ref(p);
  }
  EXPECT_GT(differ, 990);
  EXPECT_EQ(a({4.0, -7.0, 2.0}), 0.0);  // still zero on the lattice
}

TEST(OctaveSums, OneOctaveIsTheNoise) {
  const PerlinNoise noise(7);
  const glm::dvec3 p{1.3, -2.7, 0.45};
  EXPECT_EQ(fbm(noise, p, 1), noise(p));
  EXPECT_EQ(turbulence(noise, p, 1), std::abs(noise(p)));
}

TEST(OctaveSums, NormalisedWeightedSums) {
  const PerlinNoise noise(7);
  const glm::dvec3 p{1.3, -2.7, 0.45};
  const double n0 = noise(p), n1 = noise(p * 3.0), n2 = noise(p * 9.0);
  const double expected = (n0 + 0.25 * n1 + 0.0625 * n2) / 1.3125;
  EXPECT_NEAR(fbm(noise, p, 3, 3.0, 0.25), expected, 1e-15);
  const double expected_turb = (std::abs(n0) + 0.25 * std::abs(n1) + 0.0625 * std::abs(n2)) / 1.3125;
  EXPECT_NEAR(turbulence(noise, p, 3, 3.0, 0.25), expected_turb, 1e-15);
}

TEST(OctaveSums, RangesAndTriangleInequality) {
  const PerlinNoise noise(3);
  std::uint64_t s = 17;
  double fbm_lo = 0, fbm_hi = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 p = random_point(s, -40.0, 40.0);
    const double f = fbm(noise, p, 5), t = turbulence(noise, p, 5);
    ASSERT_LE(std::abs(f), kPerlinNoiseBound);
    ASSERT_GE(t, 0.0);
    ASSERT_LE(t, kPerlinNoiseBound);
    ASSERT_GE(t + 1e-15, std::abs(f));
    fbm_lo = std::min(fbm_lo, f);
    fbm_hi = std::max(fbm_hi, f);
  }
  EXPECT_LT(fbm_lo, -0.4);
  EXPECT_GT(fbm_hi, 0.4);
}

}  // namespace
}  // namespace fracref
