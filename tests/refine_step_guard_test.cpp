// The step's local checks (refine/step_guard.hpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "refine/exterior.hpp"
#include "refine/step_guard.hpp"
#include "refine_test_support.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

using test::unit_cube;

// Two faces that share only vertex 0: f = (0, 1, 2) in the plane z = 0.5 and g = (0, 3, 4), which
// rises from vertex 0 over f.
FractureSurface bowtie() {
  std::vector<glm::vec4> p = {{0.2f, 0.2f, 0.5f, 1.0f}, {0.8f, 0.2f, 0.5f, 1.0f}, {0.2f, 0.8f, 0.5f, 1.0f},
                              {0.6f, 0.3f, 0.8f, 1.0f}, {0.3f, 0.6f, 0.8f, 1.0f}};
  std::vector<glm::uvec4> f = {{0, 1, 2, 0}, {0, 3, 4, 0}};
  return make_fracture_surface(p, f, std::vector<glm::ivec2>(2, glm::ivec2(1, 0)), 2);
}

TEST(StepGuard, AFaceSwungThroughAnotherAtTheirSharedVertexIsHeld) {
  const FractureSurface s = bowtie();
  std::vector<glm::vec4> x1 = s.positions;
  x1[3].z = 0.2f;  // g now pierces f along a segment from vertex 0
  // g turns by less than 90 degrees and no junction edge is involved: the fold guard passes it.
  std::vector<glm::vec4> folded = x1;
  EXPECT_EQ(hold_folding_motion(s, s.positions, folded), 0u);
  EXPECT_TRUE(motion_crosses_stars(s, s.positions, x1));
  EXPECT_GT(hold_star_crossings(s, s.positions, x1), 0u);
  EXPECT_EQ(x1[3], s.positions[3]);
  EXPECT_FALSE(motion_crosses_stars(s, s.positions, x1));
}

TEST(StepGuard, AFaceThatPassesBesideTheOtherIsNotHeld) {
  const FractureSurface s = bowtie();
  std::vector<glm::vec4> x1 = s.positions;
  x1[3] = {0.9f, 0.9f, 0.6f, 1.0f};  // g swings aside, still above f's plane
  EXPECT_EQ(hold_star_crossings(s, s.positions, x1), 0u);
  EXPECT_EQ(x1[3], glm::vec4(0.9f, 0.9f, 0.6f, 1.0f));
}

TEST(StepGuard, AFlatFanMovedWithinItsPlaneHoldsNothing) {
  // Six faces around vertex 0, all in the plane z = 0.5 (every pair sharing only vertex 0 is
  // coplanar: the planes through the fan's edges tell them apart).
  std::vector<glm::vec4> p = {{0.5f, 0.5f, 0.5f, 1.0f}};
  for (int k = 0; k < 6; ++k)
    p.push_back({0.5f + 0.3f * std::cos(k * 1.0471976f), 0.5f + 0.3f * std::sin(k * 1.0471976f), 0.5f, 1.0f});
  std::vector<glm::uvec4> f;
  for (std::uint32_t k = 0; k < 6; ++k) f.push_back({0, 1 + k, 1 + (k + 1) % 6, 0});
  const FractureSurface s = make_fracture_surface(p, f, std::vector<glm::ivec2>(6, glm::ivec2(1, 0)), 2);
  std::vector<glm::vec4> x1 = s.positions;
  x1[0] += glm::vec4(0.05f, -0.03f, 0.0f, 0.0f);
  EXPECT_EQ(hold_star_crossings(s, s.positions, x1), 0u);
  EXPECT_EQ(hold_folding_motion(s, s.positions, x1), 0u);
}

TEST(StepGuard, TheLineSearchStopsOnlyWhereNoShorterStepLowersTheParabola) {
  // E(t) − E(0) = a·t + c·t² for a grid of slopes a and curvatures c, judged from t = 1 and 1/2.
  // Where the rule stops, the parabola must stay positive on (0, 1/2]; where the slope is not
  // negative and the step rises at both lengths, it must stop.
  int stops = 0, goes = 0;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) {
      const double a = 0.1 * i, c = 0.1 * j;
      auto rise = [&](double t) { return a * t + c * t * t; };
      const bool stop = rises_at_first_order(rise(1.0), rise(0.5));
      if (stop) {
        ++stops;
        for (int k = 1; k <= 64; ++k) EXPECT_GT(rise(0.5 * k / 64.0), 0.0) << "a " << a << " c " << c;
      } else {
        ++goes;
        if (a >= 0.0 && rise(1.0) > 0.0 && rise(0.5) > 0.0) ADD_FAILURE() << "a " << a << " c " << c;
      }
    }
  EXPECT_GT(stops, 100);
  EXPECT_GT(goes, 100);
  // Convex with a negative slope: E falls near 0 though both lengths rise; the search goes on.
  EXPECT_FALSE(rises_at_first_order(8.0 - 4.0 * 0.25, 2.0 - 2.0 * 0.25));
  EXPECT_FALSE(rises_at_first_order(1.0, -0.1));
}

}  // namespace
// With the rim sliding, a rim vertex that lands on another rim vertex's point stays where it was;
// interior vertices are not the rim's business. In the 3 x 3 sheet every vertex but the middle
// one (m) is on its rim; a, b, c are its first row.
TEST(StepGuard, ARimVertexThatLandsOnAnotherStays) {
  const FractureSurface s = example_sheet(3);
  auto at = [&](float x, float y) {
    for (std::uint32_t v = 0; v < s.positions.size(); ++v)
      if (s.positions[v] == glm::vec4(x, y, 0.0f, 1.0f)) return v;
    return std::uint32_t(0xffffffffu);
  };
  const std::uint32_t a = at(0, 0), b = at(1, 0), c = at(2, 0), m = at(1, 1);
  ASSERT_LT(std::max({a, b, c, m}), s.positions.size());
  ASSERT_FALSE(s.vertex_flags[m] & kVertexBoundary);
  const std::vector<glm::vec4> x0 = s.positions;
  std::vector<glm::vec4> x1 = x0;
  x1[a] = x0[b];  // onto a rim vertex that stays
  EXPECT_EQ(hold_coincident_rim(s, x0, x1), 1u);
  EXPECT_EQ(x1, x0);
  x1[a] = x1[c] = glm::vec4(0.5f, 0.0f, 0.0f, 1.0f);  // two onto one new point
  EXPECT_EQ(hold_coincident_rim(s, x0, x1), 2u);
  EXPECT_EQ(x1, x0);
  x1[b] = x0[c];  // onto c's point, and a onto b's: b is held, then a lands on it and is held
  x1[a] = x0[b];
  EXPECT_EQ(hold_coincident_rim(s, x0, x1), 2u);
  EXPECT_EQ(x1, x0);
  x1[m] = x0[b];  // an interior vertex onto a rim vertex: not a rim pair
  EXPECT_EQ(hold_coincident_rim(s, x0, x1), 0u);
  EXPECT_EQ(x1[m], x0[b]);
}

}  // namespace fracref
