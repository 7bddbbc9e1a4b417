// motion_filters (refine/motion_filters.hpp): the motions the flow allows a vertex of S, here the
// vertices of a T-junction's curve: across the curve where it runs on, freely where it turns back.
#include <gtest/gtest.h>

#include <vector>

#include "refine/exterior.hpp"
#include "refine/motion_filters.hpp"
#include "refine_test_support.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

double moves(const glm::dmat3& filter, const glm::dvec3& d) { return glm::length(filter * d); }

}  // namespace

// The junction runs along y through (0, 1, 0) and (0, 2, 0). Straight, a junction vertex may not
// move along it (the vertices would bunch) but may across it. Pulled out to (3, 1, 0), the curve
// turns back at (0, 1, 0)'s vertex by 37 degrees: held across the hairpin's axis (x), its tip could
// not draw back, and stayed behind as a spike while the sheets moved on; it moves freely there.
// Its neighbour, where the curve bends by less than 90 degrees, still moves across its curve.
TEST(MotionFilters, AJunctionVertexMovesAcrossItsCurveAndFreelyWhereTheCurveTurnsBack) {
  const ExteriorSurface b = make_exterior(test::unit_cube(), "cube");
  FractureSurface s = example_t_junction(3);
  const std::uint32_t tip = test::vertex_at(s, {0.0f, 1.0f, 0.0f}), next = test::vertex_at(s, {0.0f, 2.0f, 0.0f});
  ASSERT_TRUE(s.vertex_flags[tip] & kVertexNonManifold);
  std::vector<glm::dmat3> f = motion_filters(s, b);
  for (const std::uint32_t v : {tip, next}) {
    EXPECT_NEAR(moves(f[v], {0.0, 1.0, 0.0}), 0.0, 1e-12) << "along the curve, vertex " << v;
    EXPECT_NEAR(moves(f[v], {1.0, 0.0, 0.0}), 1.0, 1e-12) << "across the curve, vertex " << v;
    EXPECT_NEAR(moves(f[v], {0.0, 0.0, 1.0}), 1.0, 1e-12) << "across the curve, vertex " << v;
  }

  s.positions[tip] = glm::vec4(3.0f, 1.0f, 0.0f, 1.0f);
  f = motion_filters(s, b);
  for (const glm::dvec3& d : {glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(0.0, 0.0, 1.0)})
    EXPECT_NEAR(moves(f[tip], d), 1.0, 1e-12) << "the tip of the hairpin";
  const glm::dvec3 along = glm::normalize(glm::dvec3(0.0, 1.0, 0.0) + glm::normalize(glm::dvec3(-3.0, 1.0, 0.0)));
  EXPECT_NEAR(moves(f[next], along), 0.0, 1e-6) << "its neighbour, along its curve";
  EXPECT_NEAR(moves(f[next], {0.0, 0.0, 1.0}), 1.0, 1e-12) << "its neighbour, across its curve";
}

}  // namespace fracref
