// tuck_inside on an L-shaped prism (the notch x, y in [1, 2] is outside B): a coarse sheet whose
// boundary edge spans the notch sticks out of B, and tucking brings it inside before the flow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geom/intersect.hpp"
#include "pieces_test_support.hpp"
#include "refine/containment.hpp"
#include "refine/exterior.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// One face at z = 0.5: (0, 0) on B's corner edge, (2, 0.5) and (0.5, 2) on B; its edge between
// the last two runs across the notch.
FractureSurface sheet_over_notch() {
  const std::vector<glm::vec4> positions = {{0.0f, 0.0f, 0.5f, 1.0f}, {2.0f, 0.5f, 0.5f, 1.0f}, {0.5f, 2.0f, 0.5f, 1.0f}};
  return make_fracture_surface(positions, {{0, 1, 2, 0}}, {{1, 0}}, 2);
}

// How far S reaches outside B at most, sampled on a grid of each face.
double deepest_outside(const FractureSurface& s, const ExteriorSurface& b) {
  double worst = 0.0;
  const int n = 16;
  for (const glm::uvec4& f : s.faces)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        const glm::dvec3 x = (1.0 - u - v) * glm::dvec3(glm::vec3(s.positions[f.x])) +
                             u * glm::dvec3(glm::vec3(s.positions[f.y])) + v * glm::dvec3(glm::vec3(s.positions[f.z]));
        if (!b.contains(x)) worst = std::max(worst, std::sqrt(b.squared_distance(x)));
      }
  return worst;
}

TEST(RefineContainment, SheetAcrossANotchIsTuckedInside) {
  const ExteriorSurface b = make_exterior(pieces_test::voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0), "L prism");
  FractureSurface s = sheet_over_notch();
  RefinementTree tree = RefinementTree::identity(s.positions.size());
  const double before = deepest_outside(s, b);
  ASSERT_GT(before, 0.2);  // (1.25, 1.25) is 0.25 past both walls of the notch
  EXPECT_TRUE(face_meets_exterior(s, 0, b));
  const std::size_t splits = tuck_inside(s, tree, b, TuckOptions{b.diagonal()});
  EXPECT_GT(splits, 0u);
  EXPECT_EQ(validate(s), "");
  EXPECT_EQ(tree.parents.size(), s.positions.size());
  const double after = deepest_outside(s, b);
  EXPECT_LT(after, 0.1 * before) << "before " << before;
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    if (s.vertex_flags[v] & kVertexBoundary) {
      EXPECT_LT(std::sqrt(b.squared_distance(glm::dvec3(glm::vec3(s.positions[v])))), 1e-5) << v;
    }
  EXPECT_TRUE(find_self_intersections(double_positions(s), face_triangles(s), 1).empty());
  // Tucking again only refines the rim further toward the notch's corner.
  tuck_inside(s, tree, b, TuckOptions{b.diagonal()});
  EXPECT_EQ(validate(s), "");
  EXPECT_LE(deepest_outside(s, b), after);
}

TEST(RefineContainment, SheetInsideIsLeftAlone) {
  const ExteriorSurface b = make_exterior(pieces_test::voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0), "L prism");
  const std::vector<glm::vec4> positions = {{0.0f, 0.0f, 0.5f, 1.0f}, {2.0f, 0.5f, 0.5f, 1.0f}, {0.5f, 1.0f, 0.5f, 1.0f}};
  FractureSurface s = make_fracture_surface(positions, {{0, 1, 2, 0}}, {{1, 0}}, 2);
  RefinementTree tree = RefinementTree::identity(s.positions.size());
  EXPECT_FALSE(face_meets_exterior(s, 0, b));
  EXPECT_EQ(tuck_inside(s, tree, b, TuckOptions{b.diagonal()}), 0u);
  EXPECT_EQ(s.faces.size(), 1u);
}

// A square cross-section of the unit cube as two faces: their shared diagonal is an interior edge
// with both ends on B, which split_rim_chords splits at its midpoint.
TEST(RefineContainment, ChordBetweenTwoRimVerticesIsSplit) {
  const ExteriorSurface b = make_exterior(pieces_test::voxel_surface({{0, 0, 0}}, 1.0), "cube");
  const std::vector<glm::vec4> positions = {{0, 0, 0.5f, 1}, {1, 0, 0.5f, 1}, {1, 1, 0.5f, 1}, {0, 1, 0.5f, 1}};
  FractureSurface s = make_fracture_surface(positions, {{0, 1, 2, 0}, {0, 2, 3, 0}}, {{1, 0}, {1, 0}}, 2);
  RefinementTree tree = RefinementTree::identity(s.positions.size());
  EXPECT_EQ(split_rim_chords(s, tree, b, TuckOptions{b.diagonal()}), 1u);
  EXPECT_EQ(validate(s), "");
  ASSERT_EQ(s.positions.size(), 5u);
  EXPECT_EQ(s.faces.size(), 4u);
  EXPECT_EQ(glm::vec3(s.positions[4]), glm::vec3(0.5f, 0.5f, 0.5f));  // deep inside: not moved
  EXPECT_EQ(tree.parents[4], glm::uvec3(0, 2, 0));
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeBoundary) {
      EXPECT_FALSE((s.vertex_flags[s.edges[e].x] & kVertexBoundary) && (s.vertex_flags[s.edges[e].y] & kVertexBoundary));
    }
  }
  EXPECT_EQ(split_rim_chords(s, tree, b, TuckOptions{b.diagonal()}), 0u);
}

// The same cross-section 0.0005 over the cube's floor, with a small sheet of S floating 0.0012
// over its centre: the chord's midpoint is nearer to B than the margin (0.00173), and moved up
// to it the new faces would cut the small sheet; split at the midpoint itself they stay flat.
TEST(RefineContainment, ChordNearBIsSplitAtItsMidpointWhenTheMoveInwardIsBlocked) {
  const ExteriorSurface b = make_exterior(pieces_test::voxel_surface({{0, 0, 0}}, 1.0), "cube");
  const float z = 0.0005f, h = 0.0012f;
  const std::vector<glm::vec4> positions = {{0, 0, z, 1},          {1, 0, z, 1},          {1, 1, z, 1},
                                            {0, 1, z, 1},          {0.2f, 0.5f, h, 1},    {0.8f, 0.3f, h, 1},
                                            {0.7f, 0.8f, h, 1}};
  FractureSurface s = make_fracture_surface(positions, {{0, 1, 2, 0}, {0, 2, 3, 0}, {4, 5, 6, 0}},
                                            {{1, 0}, {1, 0}, {1, 0}}, 2);
  RefinementTree tree = RefinementTree::identity(s.positions.size());
  EXPECT_EQ(split_rim_chords(s, tree, b, TuckOptions{b.diagonal()}), 1u);
  EXPECT_EQ(validate(s), "");
  ASSERT_EQ(s.positions.size(), 8u);
  EXPECT_EQ(glm::vec3(s.positions[7]), glm::vec3(0.5f, 0.5f, z));
  EXPECT_TRUE(find_self_intersections(double_positions(s), face_triangles(s), 1).empty());
}

}  // namespace
TEST(Exterior, SelfIntersectingExteriorIsRefusedUpFrontNamingTwoFaces) {
  MeshSoup cube = pieces_test::voxel_surface({{0, 0, 0}}, 1.0);
  EXPECT_NO_THROW(make_exterior(cube, "cube.obj"));
  // Pull the corner (1, 1, 1) through the face x = 0: still closed, manifold and outward wound.
  for (glm::dvec3& p : cube.positions)
    if (p == glm::dvec3(1, 1, 1)) p = glm::dvec3(-0.5, 0.5, 0.5);
  try {
    make_exterior(cube, "cube.obj");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cube.obj: the exterior surface intersects itself: faces "), std::string::npos)
        << e.what();
  }
}

}  // namespace fracref
