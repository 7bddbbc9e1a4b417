// S crossing B near its rim, on an L-shaped prism (its inner vertical edge at x = y = 1 is a
// concave crease): a rim vertex whose inner edge leaves it outside B is retracted to where the
// edge enters B, fracture triangles that poke out of B name the vertices to push, and a push
// moves a vertex into B. Then the repairs that must not make S cross itself (boundary
// contractions) and the exact clash test of the assembled triangles.
#include <gtest/gtest.h>

#include "geom/intersect.hpp"
#include "pieces/pieces_internal.hpp"
#include "pieces_test_support.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_test;
using namespace pieces_detail;

// Unit cells (0,0), (1,0), (0,1) in x, y; z in [0, 1]. The notch is the cell (1,1).
ExteriorMesh l_prism() { return make_exterior_mesh(voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0)); }

// A fan of three faces around the inner vertex v, its rim w0 w1 w2 on B.
FractureSurface fan(const std::array<glm::vec3, 4>& p) {
  std::vector<glm::vec4> positions;
  for (const glm::vec3& x : p) positions.emplace_back(x, 1.0f);
  const std::vector<glm::uvec4> faces = {{3, 0, 1, 0}, {3, 1, 2, 0}, {3, 2, 0, 0}};
  return make_fracture_surface(positions, faces, std::vector<glm::ivec2>(3, glm::ivec2(1, 0)), 2);
}

TEST(PiecesRim, RimVertexOvershootingANotchIsRetracted) {
  const ExteriorMesh m = l_prism();
  // w0 on the notch's face x = 1; its edge to v = (1.5, 0.5, 0.5) crosses the notch and enters
  // B through the face y = 1 of cell (1,0) at x = 1 + 0.5 / 11.
  FractureSurface s = fan({glm::vec3(1.0f, 1.05f, 0.5f), glm::vec3(2.0f, 0.5f, 0.3f), glm::vec3(1.5f, 0.0f, 0.7f),
                           glm::vec3(1.5f, 0.5f, 0.5f)});
  ASSERT_EQ(s.vertex_flags[3] & kVertexBoundary, 0u);
  const std::vector<glm::vec4> before = s.positions;
  EXPECT_EQ(retract_rim(s, m, 1e-9), 1u);
  EXPECT_NEAR(s.positions[0].x, 1.0 + 0.5 / 11.0, 1e-5);
  EXPECT_NEAR(s.positions[0].y, 1.0, 1e-6);
  EXPECT_NEAR(s.positions[0].z, 0.5, 1e-6);
  for (int v = 1; v < 4; ++v) EXPECT_EQ(s.positions[v], before[v]);
  // Retracted, the rim leaves every inner edge inside B: nothing moves again.
  EXPECT_EQ(retract_rim(s, m, 1e-9), 0u);
}

TEST(PiecesRim, TrianglesPokingOutOfBNameTheirInnerVertices) {
  const ExteriorMesh m = l_prism();
  // a on B (face x = 1 of cell (0,1)), b and c inside cell (1,0): the triangle spans the notch.
  const std::vector<glm::dvec3> positions = {{1.0, 1.5, 0.5}, {1.5, 0.5, 0.2}, {1.5, 0.5, 0.8}, {0.5, 0.5, 0.5}};
  const std::vector<std::uint8_t> on_b = {1, 0, 0, 0};
  const auto poking = poking_vertices(m, positions, {{0, 1, 2}}, on_b, 4, 1e-9);
  ASSERT_EQ(poking.size(), 2u);
  EXPECT_GT(poking.at(1).distance, 0.0);
  EXPECT_GT(poking.at(2).distance, 0.0);
  // The same corner on B with inner corners that keep the triangle inside: nothing pokes.
  EXPECT_TRUE(poking_vertices(m, positions, {{0, 3, 1}}, on_b, 4, 1e-9).empty());
  // A vertex that is not of S (id >= s_vertex_count) is never named.
  EXPECT_EQ(poking_vertices(m, positions, {{0, 1, 2}}, on_b, 2, 1e-9).size(), 1u);
}

// On a thin B the side nearest to an inner vertex need not be the side its triangle pokes
// through: the push points from the poke back to B, not along the normal nearest the vertex.
TEST(PiecesRim, PokeThroughTheFarSideOfAThinBPointsThePushThatWay) {
  std::set<std::array<int, 3>> cells;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) cells.insert({i, j, 0});
  const ExteriorMesh m = make_exterior_mesh(voxel_surface(cells, 0.2));  // 2 x 2 x 0.2
  // w0 on the front z = 0.2; v 0.03 over the back z = 0; w1 a little outside the front.
  const std::vector<glm::dvec3> positions = {{0.6, 1.0, 0.2}, {1.0, 1.0, 0.03}, {1.0, 1.4, 0.26}};
  const auto poking = poking_vertices(m, positions, {{0, 1, 2}}, {1, 0, 0}, 3, 1e-9);
  ASSERT_EQ(poking.count(1), 1u);
  EXPECT_NEAR(poking.at(1).direction.z, -1.0, 1e-9);
  // Pushed that way (a quarter farther, as build_pieces does), v takes the poke back in.
  FractureSurface s = make_fracture_surface({{0.6f, 1.0f, 0.2f, 1.0f}, {1.0f, 1.0f, 0.03f, 1.0f}, {1.0f, 1.4f, 0.26f, 1.0f}},
                                            {{0, 1, 2, 0}}, {glm::ivec2(1, 0)}, 2);
  push_inward(s, m, {{1, {1.25 * poking.at(1).distance, poking.at(1).direction}}});
  EXPECT_LT(s.positions[1].z, 0.03f);
}

TEST(PiecesRim, PushMovesAVertexIntoB) {
  const ExteriorMesh m = l_prism();
  const std::array<glm::vec3, 4> corners = {glm::vec3(0.0f, 0.5f, 0.5f), glm::vec3(0.5f, 0.0f, 0.4f),
                                            glm::vec3(0.5f, 0.5f, 0.0f), glm::vec3(0.3f, 0.3f, 0.9f)};
  FractureSurface s = fan(corners);
  // v is 0.1 under the top z = 1: pushed 0.25 further down.
  push_inward(s, m, {{3, {0.25}}});
  EXPECT_NEAR(s.positions[3].z, 0.65, 1e-6);
  EXPECT_NEAR(s.positions[3].x, 0.3, 1e-6);
  // With a small triangle of S under v, a deep push drives the fan through it.
  std::vector<glm::vec4> positions;
  for (const glm::vec3& x : corners) positions.emplace_back(x, 1.0f);
  for (const glm::vec3& x : {glm::vec3(0.25f, 0.25f, 0.3f), glm::vec3(0.35f, 0.25f, 0.3f), glm::vec3(0.25f, 0.35f, 0.3f)})
    positions.emplace_back(x, 1.0f);
  const std::vector<glm::uvec4> faces = {{3, 0, 1, 0}, {3, 1, 2, 0}, {3, 2, 0, 0}, {4, 5, 6, 0}};
  FractureSurface t = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(4, glm::ivec2(1, 0)), 2);
  EXPECT_NO_THROW(push_inward(t, m, {{3, {0.05}}}));
  // A deep push that would drive the fan through the small triangle is halved until S is clean.
  const float before = t.positions[3].z;
  push_inward(t, m, {{3, {0.6}}});
  EXPECT_LT(t.positions[3].z, before);
  EXPECT_GT(t.positions[3].z, before - 0.6f + 1e-3f);
  std::vector<glm::dvec3> x;
  for (const glm::vec4& p : t.positions) x.emplace_back(glm::vec3(p));
  std::vector<TriangleIds> tris;
  for (const glm::uvec4& f : t.faces) tris.push_back({f.x, f.y, f.z});
  EXPECT_TRUE(find_self_intersections(x, tris, 1).empty());
}

// Faces of S that cross each other away from the moved vertex (the pieces stage reports those
// elsewhere) do not hold a push back: only faces at a moved vertex are checked.
TEST(PiecesRim, CrossingFacesElsewhereDoNotHoldAPushBack) {
  const ExteriorMesh m = l_prism();
  std::vector<glm::vec4> positions = {{0.0f, 0.5f, 0.5f, 1.0f}, {0.5f, 0.0f, 0.4f, 1.0f}, {0.5f, 0.5f, 0.0f, 1.0f},
                                      {0.3f, 0.3f, 0.9f, 1.0f}};
  // Two triangles through each other near the far corner of the prism.
  for (const glm::vec3& x : {glm::vec3(1.2f, 0.2f, 0.2f), glm::vec3(1.6f, 0.2f, 0.2f), glm::vec3(1.4f, 0.2f, 0.6f),
                             glm::vec3(1.4f, 0.0f, 0.3f), glm::vec3(1.4f, 0.4f, 0.3f), glm::vec3(1.4f, 0.2f, 0.7f)})
    positions.emplace_back(x, 1.0f);
  const std::vector<glm::uvec4> faces = {{3, 0, 1, 0}, {3, 1, 2, 0}, {3, 2, 0, 0}, {4, 5, 6, 0}, {7, 8, 9, 0}};
  FractureSurface t = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(5, glm::ivec2(1, 0)), 2);
  std::vector<glm::dvec3> x;
  for (const glm::vec4& p : t.positions) x.emplace_back(glm::vec3(p));
  std::vector<TriangleIds> tris;
  for (const glm::uvec4& f : t.faces) tris.push_back({f.x, f.y, f.z});
  ASSERT_EQ(find_self_intersections(x, tris, 4).size(), 1u);
  push_inward(t, m, {{3, {0.25}}});
  EXPECT_NEAR(t.positions[3].z, 0.65, 1e-6);
}

}  // namespace
}  // namespace fracref

namespace fracref {
namespace {

using namespace pieces_detail;
using namespace pieces_test;

// A boundary contraction swings the faces of the removed end over to the kept one; when that
// sweeps a face through another sheet of S, the contraction is refused.
// a = 0, b = 1, c = 2 on the rim (c between a and b), r = 3; faces (a, c, r) and (c, b, r)
// folded along c-r. Contracting c into b turns (a, c, r) into (a, b, r), which the blocker
// (vertices 4..6, clear of both old faces) pierces at q = a/2 + b/4 + r/4.
FractureSurface folded_rim(bool with_blocker) {
  const glm::dvec3 a(0, 0, 1), b(1, 0, 0), c(0.5, 0, 0), r(0.5, 1, 0), q = 0.5 * a + 0.25 * b + 0.25 * r;
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 0.5, 1)), u = glm::normalize(glm::dvec3(1, 0, -1));
  std::vector<glm::vec4> positions;
  for (const glm::dvec3& p : {a, b, c, r, q - 0.1 * n, q + 1.0 * n, q + 0.5 * n + 0.6 * u})
    positions.emplace_back(glm::vec3(p), 1.0f);
  std::vector<glm::uvec4> faces = {{0, 2, 3, 0}, {2, 1, 3, 0}};
  if (with_blocker) faces.push_back({4, 5, 6, 0});
  return make_fracture_surface(positions, faces, std::vector<glm::ivec2>(faces.size(), glm::ivec2(1, 0)), 2);
}

TEST(PiecesRepair, ContractionSweepingAFaceThroughSIsRefused) {
  const ExteriorMesh m = make_exterior_mesh(voxel_surface({{0, 0, 0}}, 1.0));
  RepairReport free_report, blocked_report;
  // Only c-b (0.5) is shorter than 0.55; the blocker's edges are longer.
  const FractureSurface free = repair_boundary(folded_rim(false), m, 0.55, false, 0.0, {}, {}, free_report);
  EXPECT_EQ(free_report.collapsed, 1u);
  ASSERT_EQ(free.faces.size(), 1u);
  EXPECT_EQ(free.faces[0], glm::uvec4(0, 1, 3, 0));
  const FractureSurface before = folded_rim(true);
  const FractureSurface blocked = repair_boundary(before, m, 0.55, false, 0.0, {}, {}, blocked_report);
  EXPECT_EQ(blocked_report.collapsed, 0u);
  EXPECT_EQ(blocked.faces, before.faces);
  EXPECT_TRUE(find_self_intersections(double_positions(blocked), face_triangles(blocked), 1).empty());
}

TEST(PiecesRepair, RequestedContractionIsMadeAndRecorded) {
  const ExteriorMesh m = make_exterior_mesh(voxel_surface({{0, 0, 0}}, 1.0));
  RepairReport report;
  const FractureSurface s = repair_boundary(folded_rim(false), m, 0.0, false, 0.0, {}, {{2, 1}, {7, 8}}, report);
  EXPECT_EQ(report.contracted, 1u);  // 7-8 is no edge: skipped
  ASSERT_EQ(s.faces.size(), 1u);
  EXPECT_EQ(s.faces[0], glm::uvec4(0, 1, 3, 0));
  EXPECT_EQ(report.face_origin, std::vector<std::uint32_t>{0});
}

// Clashes sort the crossings of the assembled triangles into what a retry moves: S vertices off
// B of a fracture triangle through a B triangle are pushed, those of two fracture triangles
// through each other are relaxed or contracted.
TEST(PiecesClashes, CrossingsNameTheMovableVertices) {
  // Fracture triangle 0-1-2 (0 on B), fracture triangle 3-4-5 through it, B triangle 6-7-8
  // through fracture triangle 0-1-2 as well; vertex 9 is not of S.
  const std::vector<glm::dvec3> x = {{0, 0, 0},  {1, 0, 0},   {0, 1, 0},   {0.2, 0.2, -1}, {0.3, 0.2, 1},
                                     {0.2, 0.3, 1}, {0.6, 0.1, -1}, {0.7, 0.1, 1}, {0.6, 0.2, 1}, {5, 5, 5}};
  const std::vector<std::uint8_t> on_b = {1, 0, 0, 0, 0, 0, 1, 1, 1, 0};
  const Clashes both = find_clashes(x, {{0, 1, 2}, {3, 4, 5}}, {{6, 7, 8}}, on_b, 6);
  EXPECT_EQ(both.pairs, 2u);
  ASSERT_EQ(both.poking.size(), 2u);
  // Pushed along the inward normal of the B triangle they cross (B is outward-facing: 6-7-8
  // faces -x -y, so inward is +x +y).
  const glm::dvec3 inward = glm::normalize(glm::dvec3(0.2, 0.2, -0.01));
  for (std::uint32_t v : {1u, 2u}) {
    ASSERT_EQ(both.poking.count(v), 1u);
    EXPECT_NEAR(glm::distance(both.poking.at(v), inward), 0.0, 1e-12);
  }
  EXPECT_EQ(both.folded, (std::set<std::uint32_t>{1, 2, 3, 4, 5}));
  const Clashes none = find_clashes(x, {{0, 1, 2}}, {{7, 8, 9}}, on_b, 6);
  EXPECT_EQ(none.pairs, 0u);
  EXPECT_TRUE(none.poking.empty() && none.folded.empty());
}

}  // namespace
}  // namespace fracref
