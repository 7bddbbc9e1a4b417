// collapse_hairpin_tips (refine/collapses.hpp) on a T-junction whose junction curve is bent at one
// vertex, and validate_edges (surface/fracture_surface.hpp), which judges the collapses locally.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "refine/collapses.hpp"
#include "refine_test_support.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

CollapseOptions limit(double degrees) {
  CollapseOptions o;
  o.max_hairpin_degrees = degrees;
  return o;
}

std::uint32_t face_count_at(const FractureSurface& s, std::uint32_t v) { return s.vf_offsets[v + 1] - s.vf_offsets[v]; }

bool junction_edge(const FractureSurface& s, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t e = find_edge(s, a, b);
  return e != kNoEdge && s.edge_special[e] == kEdgeNonManifold;
}

// The T-junction's curve runs along y, through (0, k, 0); the vertex at y = `at` moved 0.2 off it
// along x, so that the curve bends there by 23 degrees (its two junction edges 157 apart) and by
// 11 at its neighbours on the curve.
FractureSurface bent_t_junction(float at) {
  FractureSurface s = example_t_junction(4);
  s.positions[test::vertex_at(s, {0.0f, at, 0.0f})] = glm::vec4(0.2f, at, 0.0f, 1.0f);
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s), "");
  return s;
}

}  // namespace

// A limit above the bend makes the bent vertex a tip: it is collapsed into a neighbour on the
// curve, the three faces on that edge (two of the floor, one of the wall) go, and S stays valid
// with the curve running straight past it.
TEST(Collapses, ATipLosesItsFacesAndTheCurveRunsPastIt) {
  FractureSurface s = bent_t_junction(2.0f);
  const std::uint32_t tip = test::vertex_at(s, {0.2f, 2.0f, 0.0f});
  const std::uint32_t below = test::vertex_at(s, {0.0f, 1.0f, 0.0f}), above = test::vertex_at(s, {0.0f, 3.0f, 0.0f});
  const std::size_t faces = s.faces.size(), vertices = s.positions.size();
  const std::vector<std::uint32_t> tips = collapse_hairpin_tips(s, limit(160.0));
  ASSERT_EQ(tips, std::vector<std::uint32_t>{tip});
  EXPECT_EQ(validate(s), "");
  EXPECT_EQ(s.faces.size(), faces - 3);
  EXPECT_EQ(s.positions.size(), vertices);
  EXPECT_EQ(face_count_at(s, tip), 0u);
  EXPECT_TRUE(junction_edge(s, below, above));
  EXPECT_EQ(s.piece_count, 3);
}

// Straight, or bent less sharply than the limit, the curve has no tip; a limit of 0 is off.
TEST(Collapses, NoTipWhereTheCurveBendsLessThanTheLimitOrTheLimitIsZero) {
  FractureSurface straight = example_t_junction(4);
  EXPECT_TRUE(collapse_hairpin_tips(straight, limit(179.0)).empty());
  FractureSurface bent = bent_t_junction(2.0f);
  EXPECT_TRUE(collapse_hairpin_tips(bent, limit(150.0)).empty());
  EXPECT_TRUE(collapse_hairpin_tips(bent, limit(0.0)).empty());
  EXPECT_EQ(validate(bent), "");
}

// Next to B the tip goes into its neighbour inside S, not into the one on B; and a collapse the
// caller refuses (the refiner's contact rule with B) is not made.
TEST(Collapses, ATipIsNotCollapsedOntoBNorWhereTheCallerRefusesAMovedFace) {
  FractureSurface s = bent_t_junction(1.0f);
  const std::uint32_t tip = test::vertex_at(s, {0.2f, 1.0f, 0.0f});
  const std::uint32_t on_b = test::vertex_at(s, {0.0f, 0.0f, 0.0f}), inside = test::vertex_at(s, {0.0f, 2.0f, 0.0f});
  ASSERT_TRUE(s.vertex_flags[on_b] & kVertexBoundary);
  FractureSurface refused = s;
  CollapseOptions o = limit(160.0);
  o.reject_face = [](const glm::uvec4&) { return true; };
  EXPECT_TRUE(collapse_hairpin_tips(refused, o).empty());
  ASSERT_EQ(collapse_hairpin_tips(s, limit(160.0)), std::vector<std::uint32_t>{tip});
  EXPECT_EQ(validate(s), "");
  EXPECT_TRUE(junction_edge(s, on_b, inside));
}

// validate_edges names an edge around which the pieces no longer close up, and passes the others.
TEST(ValidateEdges, NamesTheEdgeWhereAFacesPiecesAreWrong) {
  FractureSurface s = example_t_junction(2);
  std::vector<std::uint32_t> all(s.edges.size());
  for (std::uint32_t e = 0; e < all.size(); ++e) all[e] = e;
  EXPECT_EQ(validate_edges(s, all), "");
  const std::uint32_t a = test::vertex_at(s, {0.0f, 0.0f, 0.0f}), b = test::vertex_at(s, {0.0f, 0.0f, 1.0f});
  const std::uint32_t wall_edge = find_edge(s, a, b);
  ASSERT_NE(wall_edge, kNoEdge);
  const std::uint32_t f = s.ef_faces[s.ef_offsets[wall_edge]];
  std::swap(s.face_pieces[f].x, s.face_pieces[f].y);
  std::vector<std::uint32_t> at_f, away;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const auto begin = s.ef_faces.begin() + s.ef_offsets[e], end = s.ef_faces.begin() + s.ef_offsets[e + 1];
    (std::find(begin, end, f) != end ? at_f : away).push_back(e);
  }
  EXPECT_NE(validate_edges(s, at_f), "");
  EXPECT_EQ(validate_edges(s, away), "");
  EXPECT_NE(validate(s), "");
}

}  // namespace fracref
