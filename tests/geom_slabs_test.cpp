// Diagonal slabs: apart only for sets more than twice the pad apart, through every rounding.
#include <gtest/gtest.h>

#include <random>

#include "geom/slabs.hpp"

namespace {

using fracref::Slabs;
using fracref::segment_slabs;
using fracref::slabs_apart;
using glm::dvec3;

// Two parallel segments along (1, -1, 0), a tenth apart along (1, 1, 0): their boxes overlap.
TEST(GeomSlabs, SegmentsApartAlongAFaceDiagonalWhereTheirBoxesOverlap) {
  const Slabs a = segment_slabs({0, 1, 0}, {1, 0, 0}, 0.0);
  const Slabs b = segment_slabs({0.1, 1, 0}, {1, 0.1, 0}, 0.0);
  EXPECT_TRUE(slabs_apart(a, b));
  EXPECT_TRUE(slabs_apart(b, a));
  EXPECT_FALSE(slabs_apart(a, a));
  // Padded by more than half their distance (0.1 / sqrt 2), they are not apart any more.
  EXPECT_FALSE(slabs_apart(segment_slabs({0, 1, 0}, {1, 0, 0}, 0.036), segment_slabs({0.1, 1, 0}, {1, 0.1, 0}, 0.036)));
  EXPECT_TRUE(slabs_apart(segment_slabs({0, 1, 0}, {1, 0, 0}, 0.035), segment_slabs({0.1, 1, 0}, {1, 0.1, 0}, 0.035)));
}

TEST(GeomSlabs, MergedSlabsHoldBothAndTouchingSlabsAreNotApart) {
  Slabs both;
  const Slabs empty;
  EXPECT_TRUE(slabs_apart(both, segment_slabs({0, 0, 0}, {0, 0, 0}, 0.0)));  // the empty set is apart from all
  merge(both, segment_slabs({0, 0, 0}, {1, 0, 0}, 0.0));
  merge(both, segment_slabs({0, 1, 0}, {0, 1, 1}, 0.0));
  merge(both, empty);
  for (const dvec3& p : {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 1, 1), dvec3(0.5, 0.5, 0.5)})
    EXPECT_FALSE(slabs_apart(both, segment_slabs(p, p, 0.0))) << p.x << " " << p.y << " " << p.z;
  // Touching at one point (0, 1, 1): not apart.
  EXPECT_FALSE(slabs_apart(segment_slabs({0, 1, 1}, {1, 2, 2}, 0.0), segment_slabs({0, 1, 1}, {-1, 0, 0}, 0.0)));
  EXPECT_TRUE(slabs_apart(both, segment_slabs({2, 2, 2}, {3, 3, 3}, 0.0)));
  // A triangle's slabs hold its centroid; a point just off its hypotenuse, inside its box, is apart.
  const dvec3 tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Slabs t = fracref::point_slabs(tri, 3, 0.0);
  EXPECT_FALSE(slabs_apart(t, segment_slabs({1.0 / 3, 1.0 / 3, 0}, {1.0 / 3, 1.0 / 3, 0}, 0.0)));
  EXPECT_TRUE(slabs_apart(t, segment_slabs({0.51, 0.51, 0}, {0.51, 0.51, 0}, 0.0)));
  // 0.02 / sqrt 2 off it: apart with both padded by 0.007, not with both padded by 0.0071.
  EXPECT_TRUE(slabs_apart(fracref::point_slabs(tri, 3, 0.007), segment_slabs({0.51, 0.51, 0}, {0.51, 0.51, 0}, 0.007)));
  EXPECT_FALSE(slabs_apart(fracref::point_slabs(tri, 3, 0.0071), segment_slabs({0.51, 0.51, 0}, {0.51, 0.51, 0}, 0.0071)));
}

// Points closer than twice the pad are never apart, wherever they lie (coordinates up to 1e6
// with pads down to 1e-9: the float rounding is far coarser than the pad) and in any direction.
TEST(GeomSlabs, PointsWithinTwiceThePadAreNeverApart) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int apart = 0;
  for (int k = 0; k < 20000; ++k) {
    const double scale = std::pow(10.0, 6.0 * (unit(rng) + 1.0) / 2.0);
    const double pad = std::pow(10.0, -9.0 + 8.0 * (unit(rng) + 1.0) / 2.0);
    const dvec3 p = scale * dvec3(unit(rng), unit(rng), unit(rng));
    dvec3 d(unit(rng), unit(rng), unit(rng));
    d = glm::normalize(d);
    const dvec3 q = p + d * (2.0 * pad * (1.0 - 1e-9));
    ASSERT_FALSE(slabs_apart(segment_slabs(p, p, pad), segment_slabs(q, q, pad))) << k;
    // Far beyond the pad along a diagonal: apart when the floats can tell (always at this scale).
    const dvec3 far = p + dvec3(1.0, 1.0, 0.0) * (4.0 * pad + 1e-5 * scale);
    apart += slabs_apart(segment_slabs(p, p, pad), segment_slabs(far, far, pad));
  }
  EXPECT_EQ(apart, 20000);
}

}  // namespace
