// mesh_stats: exact topology counts on small hand-made soups, and its JSON.
#include <string>

#include <gtest/gtest.h>

#include "io/mesh_stats.hpp"
#include "util/error.hpp"

using namespace fracref;

namespace {

MeshSoup soup(std::vector<glm::dvec3> p, std::vector<std::array<std::uint32_t, 3>> t) {
  MeshSoup s;
  s.positions = std::move(p);
  s.triangles = std::move(t);
  s.polygons = s.triangles.size();
  return s;
}

MeshSoup tetrahedron(glm::dvec3 o = glm::dvec3(0.0)) {
  return soup({o, o + glm::dvec3(1, 0, 0), o + glm::dvec3(0, 1, 0), o + glm::dvec3(0, 0, 1)},
              {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}});
}

// b appended to a, its indices shifted.
MeshSoup join(MeshSoup a, const MeshSoup& b) {
  auto offset = static_cast<std::uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return a;
}

}  // namespace

TEST(MeshStats, ClosedTetrahedron) {
  MeshStats s = mesh_stats(tetrahedron());
  EXPECT_EQ(s.vertices, 4u);
  EXPECT_EQ(s.faces, 4u);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.non_manifold_vertices, 0u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.bbox_min, glm::dvec3(0.0));
  EXPECT_EQ(s.bbox_max, glm::dvec3(1.0));
}

TEST(MeshStats, FinOfThreeTrianglesOnOneEdge) {
  MeshStats s = mesh_stats(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                                {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  EXPECT_EQ(s.vertices, 5u);
  EXPECT_EQ(s.faces, 3u);
  EXPECT_EQ(s.non_manifold_edges, 1u);
  EXPECT_EQ(s.boundary_edges, 6u);
  EXPECT_EQ(s.non_manifold_vertices, 0u);  // the three triangles are one edge-connected fan
  EXPECT_EQ(s.components, 1u);
  EXPECT_FALSE(s.closed);
}

TEST(MeshStats, OpenTetrahedronHasThreeBoundaryEdges) {
  MeshSoup t = tetrahedron();
  t.triangles.pop_back();
  MeshStats s = mesh_stats(t);
  EXPECT_EQ(s.boundary_edges, 3u);
  EXPECT_FALSE(s.closed);
  EXPECT_EQ(s.components, 1u);
}

TEST(MeshStats, BowTieVertexIsNonManifold) {
  MeshStats s = mesh_stats(soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                {{0, 1, 2}, {0, 3, 4}}));
  EXPECT_EQ(s.non_manifold_vertices, 1u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.components, 1u);  // sharing a vertex connects
}

TEST(MeshStats, TwoTetrahedraTouchingAtATipAreClosedButNonManifold) {
  MeshSoup a = tetrahedron();
  MeshSoup b = tetrahedron(glm::dvec3(-1, -1, -1));
  b.positions.pop_back();  // b's apex (0,0,0) becomes a's vertex 0
  for (auto& t : b.triangles)
    for (auto& v : t) v = v == 3 ? 0 : v + 4;
  MeshSoup both = a;
  both.positions.insert(both.positions.end(), b.positions.begin(), b.positions.end());
  both.triangles.insert(both.triangles.end(), b.triangles.begin(), b.triangles.end());
  MeshStats s = mesh_stats(both);
  EXPECT_EQ(s.vertices, 7u);
  EXPECT_EQ(s.faces, 8u);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.non_manifold_vertices, 1u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.bbox_min, glm::dvec3(-1.0));
}

TEST(MeshStats, ComponentsIgnoreUnusedVertices) {
  MeshSoup s = join(tetrahedron(), tetrahedron(glm::dvec3(5, 0, 0)));
  s.positions.emplace_back(-3, 9, 2);  // unused: no component, but inside the bbox
  MeshStats st = mesh_stats(s);
  EXPECT_EQ(st.components, 2u);
  EXPECT_EQ(st.vertices, 9u);
  EXPECT_TRUE(st.closed);
  EXPECT_EQ(st.bbox_min, glm::dvec3(-3, 0, 0));
  EXPECT_EQ(st.bbox_max, glm::dvec3(6, 9, 2));
}

TEST(MeshStats, DoubleCoveredEdgeWithOppositeWindingIsManifold) {
  // Inconsistent winding does not change edge counts: edges are undirected.
  MeshStats s = mesh_stats(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 2, 3}}));
  EXPECT_EQ(s.boundary_edges, 4u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
}

TEST(MeshStats, EmptySoupIsNotClosed) {
  MeshStats s = mesh_stats(MeshSoup{});
  EXPECT_FALSE(s.closed);
  EXPECT_EQ(s.components, 0u);
  EXPECT_EQ(s.bbox_min, glm::dvec3(0.0));
  MeshSoup points;
  points.positions = {{1, 2, 3}};
  MeshStats p = mesh_stats(points);
  EXPECT_EQ(p.components, 0u);
  EXPECT_EQ(p.bbox_max, glm::dvec3(1, 2, 3));
}

TEST(MeshStats, PolygonsTriangulatedIsCopied) {
  MeshSoup s = soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  s.polygons = 1;
  s.polygons_triangulated = 1;
  EXPECT_EQ(mesh_stats(s).polygons_triangulated, 1u);
  EXPECT_EQ(mesh_stats(s).boundary_edges, 4u);
}

TEST(MeshStats, OutOfRangeIndexIsARunError) {
  EXPECT_THROW(mesh_stats(soup({{0, 0, 0}}, {{0, 1, 2}})), RunError);
}

TEST(MeshStats, Json) {
  MeshSoup t = tetrahedron();
  t.positions[1].x = 0.1;
  EXPECT_EQ(mesh_stats_json(mesh_stats(t)),
            "{\"vertices\": 4, \"faces\": 4, \"boundary_edges\": 0, \"non_manifold_edges\": 0, "
            "\"non_manifold_vertices\": 0, \"components\": 1, \"closed\": true, "
            "\"bbox\": {\"min\": [0, 0, 0], \"max\": [0.10000000000000001, 1, 1]}, \"polygons_triangulated\": 0}");
}
