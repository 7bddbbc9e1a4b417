// The OpenMesh bridge: exact round trips in double precision, and every triangle OpenMesh would
// refuse is an InputError that says which face and why.
#include <string>

#include <gtest/gtest.h>

#include "io/openmesh_bridge.hpp"
#include "util/error.hpp"

using namespace fracref;

namespace {

MeshSoup soup(std::vector<glm::dvec3> p, std::vector<std::array<std::uint32_t, 3>> t) {
  MeshSoup s;
  s.positions = std::move(p);
  s.triangles = std::move(t);
  s.polygons = s.triangles.size();
  for (std::uint32_t i = 0; i < s.triangles.size(); ++i) s.triangle_polygon.push_back(i);
  return s;
}

MeshSoup tetrahedron() {
  return soup({{0.1, 1.0 / 3.0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}});
}

// The message of the InputError to_trimesh raises for `s`, or "<no error>".
std::string rejection(const MeshSoup& s) {
  try {
    to_trimesh(s, "piece.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "<no error>";
}

}  // namespace

TEST(OpenMeshBridge, TetrahedronRoundTripsExactly) {
  MeshSoup s = tetrahedron();
  TriMesh m = to_trimesh(s, "tetra");
  EXPECT_EQ(m.n_vertices(), 4u);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_EQ(m.point(m.vertex_handle(0))[1], 1.0 / 3.0);  // double, not float
  for (auto vh : m.vertices()) EXPECT_FALSE(m.is_boundary(vh));
  MeshSoup r = from_trimesh(m);
  EXPECT_EQ(r.positions, s.positions);
  EXPECT_EQ(r.triangles, s.triangles);
  EXPECT_EQ(r.triangle_polygon, s.triangle_polygon);
  EXPECT_EQ(r.polygons, 4u);
}

TEST(OpenMeshBridge, UnusedVerticesKeepTheirIndices) {
  MeshSoup s = soup({{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{1, 2, 3}});
  TriMesh m = to_trimesh(s, "x");
  EXPECT_EQ(m.n_vertices(), 4u);
  EXPECT_EQ(from_trimesh(m).triangles, s.triangles);
}

TEST(OpenMeshBridge, FinIsRejected) {
  MeshSoup fin = soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ(rejection(fin), "piece.obj: face 2 (0 1 4) would make edge 0-1 non-manifold");
  EXPECT_THROW(to_trimesh(fin, "fin"), InputError);
}

TEST(OpenMeshBridge, InconsistentWindingIsRejected) {
  MeshSoup s = soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  EXPECT_EQ(rejection(s), "piece.obj: face 1 (0 1 3) uses edge 0-1 in the same direction as face 0 (inconsistent winding)");
}

TEST(OpenMeshBridge, SecondFanAtAnInteriorVertexIsRejected) {
  // Vertex 0 is closed off by the tetrahedron; one more triangle touching only it cannot fit.
  MeshSoup s = tetrahedron();
  s.positions.push_back({-1, 0, 0});
  s.positions.push_back({-1, -1, 0});
  s.triangles.push_back({0, 4, 5});
  EXPECT_EQ(rejection(s), "piece.obj: face 4 (0 4 5) would make vertex 0 non-manifold");
}

TEST(OpenMeshBridge, BoundaryBowTieIsAccepted) {
  // Two fans meeting at a boundary vertex: the halfedge structure holds it without duplication.
  MeshSoup s = soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}});
  TriMesh m = to_trimesh(s, "x");
  EXPECT_EQ(m.n_vertices(), 5u);
  EXPECT_EQ(from_trimesh(m).triangles, s.triangles);
}

TEST(OpenMeshBridge, DegenerateAndOutOfRangeTrianglesAreRejected) {
  EXPECT_EQ(rejection(soup({{0, 0, 0}, {1, 0, 0}}, {{0, 1, 1}})), "piece.obj: face 0 (0 1 1) repeats a vertex");
  EXPECT_EQ(rejection(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}})),
            "piece.obj: face 0 (0 1 3) references vertex 3 of 3");
}

TEST(OpenMeshBridge, FromTrimeshSkipsDeletedElements) {
  TriMesh m = to_trimesh(tetrahedron(), "x");
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  m.delete_vertex(m.vertex_handle(3), true);  // removes the three faces around it
  MeshSoup r = from_trimesh(m);
  ASSERT_EQ(r.positions.size(), 3u);
  ASSERT_EQ(r.triangles.size(), 1u);
  EXPECT_EQ(r.triangles[0], (std::array<std::uint32_t, 3>{0, 2, 1}));
}
