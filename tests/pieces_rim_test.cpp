// S crossing B near its rim, on an L-shaped prism (its inner vertical edge at x = y = 1 is a
// concave crease): a rim vertex whose inner edge leaves it outside B is retracted to where the
// edge enters B, fracture triangles that poke out of B name the vertices to push, and a push
// moves a vertex into B.
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
  EXPECT_GT(poking.at(1), 0.0);
  EXPECT_GT(poking.at(2), 0.0);
  // The same corner on B with inner corners that keep the triangle inside: nothing pokes.
  EXPECT_TRUE(poking_vertices(m, positions, {{0, 3, 1}}, on_b, 4, 1e-9).empty());
  // A vertex that is not of S (id >= s_vertex_count) is never named.
  EXPECT_EQ(poking_vertices(m, positions, {{0, 1, 2}}, on_b, 2, 1e-9).size(), 1u);
}

TEST(PiecesRim, PushMovesAVertexIntoB) {
  const ExteriorMesh m = l_prism();
  const std::array<glm::vec3, 4> corners = {glm::vec3(0.0f, 0.5f, 0.5f), glm::vec3(0.5f, 0.0f, 0.4f),
                                            glm::vec3(0.5f, 0.5f, 0.0f), glm::vec3(0.3f, 0.3f, 0.9f)};
  FractureSurface s = fan(corners);
  // v is 0.1 under the top z = 1: pushed 0.25 further down.
  push_inward(s, m, {{3, 0.25}});
  EXPECT_NEAR(s.positions[3].z, 0.65, 1e-6);
  EXPECT_NEAR(s.positions[3].x, 0.3, 1e-6);
  // With a small triangle of S under v, a deep push drives the fan through it.
  std::vector<glm::vec4> positions;
  for (const glm::vec3& x : corners) positions.emplace_back(x, 1.0f);
  for (const glm::vec3& x : {glm::vec3(0.25f, 0.25f, 0.3f), glm::vec3(0.35f, 0.25f, 0.3f), glm::vec3(0.25f, 0.35f, 0.3f)})
    positions.emplace_back(x, 1.0f);
  const std::vector<glm::uvec4> faces = {{3, 0, 1, 0}, {3, 1, 2, 0}, {3, 2, 0, 0}, {4, 5, 6, 0}};
  FractureSurface t = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(4, glm::ivec2(1, 0)), 2);
  EXPECT_NO_THROW(push_inward(t, m, {{3, 0.05}}));
  // A deep push that would drive the fan through the small triangle is halved until S is clean.
  const float before = t.positions[3].z;
  push_inward(t, m, {{3, 0.6}});
  EXPECT_LT(t.positions[3].z, before);
  EXPECT_GT(t.positions[3].z, before - 0.6f + 1e-3f);
  std::vector<glm::dvec3> x;
  for (const glm::vec4& p : t.positions) x.emplace_back(glm::vec3(p));
  std::vector<TriangleIds> tris;
  for (const glm::uvec4& f : t.faces) tris.push_back({f.x, f.y, f.z});
  EXPECT_TRUE(find_self_intersections(x, tris, 1).empty());
}

}  // namespace
}  // namespace fracref
