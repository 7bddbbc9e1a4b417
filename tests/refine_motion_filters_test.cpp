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

// A junction curve with an exact right-angle corner, as a tet lattice's junctions have: the
// curve's vertex at y = 1 pulled out to x = 1, its two edges leave it at exactly 90 degrees (dot
// product 0). It must move along its curvature (towards the curve's inside, -x, and across, z)
// and not along the curve (y). Before, the tangent was taken from the edges as stored, from the
// lower vertex id: where the corner's id was the lowest or highest of the three, both edges
// pointed the same way from it, their sum (the curvature's direction) was taken for the tangent,
// and the corner was held there: it could not round off, and the flow turned it into a hairpin
// (the Jell-O demo's junction corners). So the corner is given each id in turn.
TEST(MotionFilters, AJunctionCornerAtARightAngleRoundsOffAndDoesNotSlideAlongItsCurve) {
  const ExteriorSurface b = make_exterior(test::unit_cube(), "cube");
  const FractureSurface t = example_t_junction(3);
  const std::uint32_t original = test::vertex_at(t, {0.0f, 1.0f, 0.0f});
  for (std::uint32_t id = 0; id < t.positions.size(); ++id) {
    FractureSurface s = t;  // the corner renumbered as `id`: the two vertices swap ids
    auto swapped = [&](std::uint32_t v) { return v == original ? id : (v == id ? original : v); };
    for (glm::uvec4& f : s.faces) f = glm::uvec4(swapped(f.x), swapped(f.y), swapped(f.z), f.w);
    std::swap(s.positions[original], s.positions[id]);
    std::swap(s.vertex_flags[original], s.vertex_flags[id]);
    rebuild_adjacency(s);
    ASSERT_EQ(validate(s), "");
    s.positions[id] = glm::vec4(1.0f, 1.0f, 0.0f, 1.0f);
    const std::vector<glm::dmat3> f = motion_filters(s, b);
    EXPECT_NEAR(moves(f[id], {0.0, 1.0, 0.0}), 0.0, 1e-12) << "along the curve, corner id " << id;
    EXPECT_NEAR(moves(f[id], {1.0, 0.0, 0.0}), 1.0, 1e-12) << "along its curvature, corner id " << id;
    EXPECT_NEAR(moves(f[id], {0.0, 0.0, 1.0}), 1.0, 1e-12) << "across, corner id " << id;
  }
}

}  // namespace fracref
