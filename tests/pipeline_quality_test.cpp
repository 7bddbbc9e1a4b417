// pipeline/quality: how much weak material a surface has within reach.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "pipeline/quality.hpp"
#include "refine_test_support.hpp"

namespace fracref {
namespace {

// A square sheet in the plane z = 0.5 over [0, 1]², split n × n.
FractureSurface square(int n) { return test::sheet(n, 0.5f); }

// ζ on [-1, 1]³ at a 0.05 cell: 1, and 0 at the nodes where weak(node) holds.
Grid3 field(const std::function<bool(const glm::dvec3&)>& weak) {
  return test::grid_of(glm::dvec3(-1.0), 0.05, 41, [&](const glm::dvec3& p) { return weak(p) ? 0.0 : 1.0; });
}

bool in_slab(const glm::dvec3& p) { return p.z > 0.64 && p.z < 0.76; }

// A weak slab parallel to the sheet, its nodes from z = 0.65 to 0.75: ζ < 0.5 past z = 0.625 (half
// a cell before the first weak node), 0.125 from the sheet, reached at the first half-cell step past it, 0.15.
TEST(WeakReach, AWeakSlabIsInReachOnlyFromItsDistanceOn) {
  const FractureSurface s = square(4);
  const Grid3 zeta = field(in_slab);
  EXPECT_EQ(weak_reach(s, zeta, 0.5, 0.1, 1.0).fraction, 0.0);
  EXPECT_EQ(weak_reach(s, zeta, 0.5, 0.2, 1.0).fraction, 1.0);
  EXPECT_NEAR(weak_reach(s, zeta, 0.5, 0.0, 1.0).half_radius, 0.15, 1e-12);
  // Lengths are fractions of the diagonal: at a diagonal of 2, the slab is 0.075 away.
  EXPECT_NEAR(weak_reach(s, zeta, 0.5, 0.0, 2.0).half_radius, 0.075, 1e-12);
  EXPECT_EQ(weak_reach(s, zeta, 0.5, 0.08, 2.0).fraction, 1.0);
}

TEST(WeakReach, OnlyTheAreaOverTheWeakPartCountsAndTheSearchHasAnEnd) {
  const FractureSurface s = square(8);
  const WeakReach half = weak_reach(s, field([](const glm::dvec3& p) { return in_slab(p) && p.x > 0.51; }), 0.5, 0.2, 1.0);
  EXPECT_GT(half.fraction, 0.4);
  EXPECT_LT(half.fraction, 0.6);
  // Beyond the search (here 0.1 of the diagonal) nothing is in reach, and no radius gives half.
  const WeakReach none = weak_reach(s, field(in_slab), 0.5, 1.0, 1.0, 0.1);
  EXPECT_EQ(none.fraction, 0.0);
  EXPECT_TRUE(std::isinf(none.half_radius));
  // Weak material on the sheet itself is at distance 0, either side of it.
  EXPECT_EQ(weak_reach(s, field([](const glm::dvec3& p) { return std::abs(p.z - 0.5) < 0.01; }), 0.5, 0.0, 1.0).fraction, 1.0);
  const WeakReach below = weak_reach(s, field([](const glm::dvec3& p) { return p.z < 0.36 && p.z > 0.24; }), 0.5, 0.2, 1.0);
  EXPECT_EQ(below.fraction, 1.0);
}

}  // namespace
}  // namespace fracref
