// The coarse model of labelled tet meshes: S, hull, pieces, welding of duplicated vertices,
// orientation, and the validity errors.
#include <gtest/gtest.h>

#include <algorithm>

#include "coarse/coarse_model.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {
using test::count_edges;
using test::input_error;
using test::kuhn_box;

int count_pieces(const CoarseModel& m, int piece) { return int(std::count(m.tet_piece.begin(), m.tet_piece.end(), piece)); }

glm::dvec3 face_normal(const FractureSurface& s, std::size_t f) {
  const glm::dvec3 a(s.positions[s.faces[f].x]), b(s.positions[s.faces[f].y]), c(s.positions[s.faces[f].z]);
  return glm::cross(b - a, c - a);
}

TEST(CoarseTets, TwoPiecesOfABoxMeetInOnePlane) {
  const TetMesh mesh = kuhn_box(2, 2, 4, [](glm::dvec3 c) { return c.z < 2 ? 0 : 5; });
  const CoarseModel m = build_tet_model(mesh, nullptr);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.tets.size(), 96u);
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(count_pieces(m, 0), 48);
  EXPECT_EQ(count_pieces(m, 1), 48);
  EXPECT_EQ(m.surface.face_count(), 8u);  // a 2x2 square of unit squares, 2 triangles each
  EXPECT_EQ(m.surface.vertex_count(), 9u);
  EXPECT_EQ(count_edges(m.surface, kEdgeBoundary), 8);
  EXPECT_EQ(count_edges(m.surface, kEdgeNonManifold), 0);
  EXPECT_EQ(m.hull.size(), 80u);  // 2*(2*2) + 4*(2*4) unit squares, 2 triangles each
  EXPECT_EQ(m.hull_piece.size(), 80u);
  EXPECT_EQ(m.inverted_fixed, 0u);
  EXPECT_EQ(m.virtual_faces_added, 0u);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"label 0", "label 5"}));
  for (std::size_t f = 0; f < m.surface.face_count(); ++f) {
    EXPECT_EQ(m.surface.face_pieces[f], glm::ivec2(1, 0));  // front = the larger piece, above
    EXPECT_GT(face_normal(m.surface, f).z, 0.0);
  }
  // S's vertices in ascending model order, all on the plane z = 2.
  EXPECT_TRUE(std::is_sorted(m.surface_to_model_vertex.begin(), m.surface_to_model_vertex.end()));
  for (std::uint32_t v : m.surface_to_model_vertex) EXPECT_EQ(m.vertices[v].z, 2.0);
  // Every vertex of S is seen by both pieces, through the same (unduplicated) model vertex.
  ASSERT_EQ(m.surface.copies.size(), 18u);
  for (std::uint32_t s = 0; s < 9; ++s)
    for (std::uint32_t k = m.surface.copy_offsets[s]; k < m.surface.copy_offsets[s + 1]; ++k)
      EXPECT_EQ(m.surface_copy_model_vertex[k], m.surface_to_model_vertex[s]);
}

TEST(CoarseTets, HullIsWoundOutward) {
  const TetMesh mesh = kuhn_box(1, 1, 2, [](glm::dvec3 c) { return c.z < 1 ? 0 : 1; });
  const CoarseModel m = build_tet_model(mesh, nullptr);
  const glm::dvec3 center(0.5, 0.5, 1.0);
  ASSERT_EQ(m.hull.size(), 20u);
  double volume = 0.0;
  for (const glm::uvec3& h : m.hull) {
    const glm::dvec3 a = m.vertices[h.x], b = m.vertices[h.y], c = m.vertices[h.z];
    volume += glm::dot(a - center, glm::cross(b - center, c - center)) / 6.0;
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - center), 0.0);
  }
  EXPECT_NEAR(volume, 2.0, 1e-12);
}

TEST(CoarseTets, TJunctionOfThreePieces) {
  // Piece 0 below z = 2; above it, pieces 1 (x < 1) and 2 (x > 1): the wall x = 1 meets the floor.
  const TetMesh mesh = kuhn_box(2, 2, 4, [](glm::dvec3 c) { return c.z < 2 ? 0 : (c.x < 1 ? 1 : 2); });
  const CoarseModel m = build_tet_model(mesh, nullptr);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.surface.face_count(), 16u);  // 8 on the floor z = 2, 8 on the wall x = 1 above it
  EXPECT_EQ(count_edges(m.surface, kEdgeNonManifold), 2);  // the line x = 1, z = 2
  EXPECT_EQ(m.surface.vertex_count(), 9u + 6u);
  int floor_faces = 0, wall_faces = 0;
  for (std::size_t f = 0; f < m.surface.face_count(); ++f) {
    const glm::ivec2 p = m.surface.face_pieces[f];
    EXPECT_GT(p.x, p.y);
    if (p.y == 0) ++floor_faces;
    if (p == glm::ivec2(2, 1)) {
      ++wall_faces;
      EXPECT_GT(face_normal(m.surface, f).x, 0.0);
    }
  }
  EXPECT_EQ(floor_faces, 8);
  EXPECT_EQ(wall_faces, 8);
}

TEST(CoarseTets, InvertedTetsAreReorientedAndCounted) {
  TetMesh mesh = kuhn_box(2, 2, 4, [](glm::dvec3 c) { return c.z < 2 ? 0 : 1; });
  for (std::size_t t = 0; t < mesh.tets.size(); t += 3) std::swap(mesh.tets[t].x, mesh.tets[t].y);
  const CoarseModel m = build_tet_model(mesh, nullptr);
  EXPECT_EQ(m.inverted_fixed, 32u);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.surface.face_count(), 8u);
  EXPECT_EQ(m.hull.size(), 80u);
}

TEST(CoarseTets, DuplicatedVerticesSeparateOneLabelIntoTwoPieces) {
  // What a simulator leaves: one label, but the tets above z = 1 use their own copies of the
  // vertices of the plane z = 1 (the crack opened there).
  TetMesh mesh = kuhn_box(2, 2, 2, [](glm::dvec3) { return 7; });
  std::vector<std::uint32_t> copy(mesh.vertices.size());
  for (std::uint32_t v = 0; v < copy.size(); ++v) {
    copy[v] = v;
    if (mesh.vertices[v].z == 1.0) copy[v] = std::uint32_t(mesh.vertices.size()), mesh.vertices.push_back(mesh.vertices[v]);
  }
  for (glm::uvec4& t : mesh.tets) {
    const double zmax = std::max({mesh.vertices[t.x].z, mesh.vertices[t.y].z, mesh.vertices[t.z].z, mesh.vertices[t.w].z});
    if (zmax > 1.0)
      for (int i = 0; i < 4; ++i) t[i] = copy[t[i]];
  }
  const CoarseModel m = build_tet_model(mesh, nullptr);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.vertices.size(), 27u + 9u);
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"label 7", "label 7, part 2"}));
  EXPECT_EQ(m.surface.face_count(), 8u);
  EXPECT_EQ(m.hull.size(), 48u);
  EXPECT_EQ(m.virtual_faces_added, 0u);
  for (std::uint32_t v = 27; v < 36; ++v) EXPECT_LT(m.vertex_weld[v], 27u);
  // Piece 0 (below) sees S through the original vertices, piece 1 through the copies.
  for (std::uint32_t s = 0; s < m.surface.vertex_count(); ++s) {
    ASSERT_EQ(m.surface.copy_offsets[s + 1] - m.surface.copy_offsets[s], 2u);
    const std::uint32_t k = m.surface.copy_offsets[s];
    EXPECT_EQ(m.surface.copies[k].x, 0u);
    EXPECT_EQ(m.surface_copy_model_vertex[k], m.surface_to_model_vertex[s]);
    EXPECT_EQ(m.surface_copy_model_vertex[k + 1], copy[m.surface_to_model_vertex[s]]);
  }
}

TEST(CoarseTets, DisconnectedLabelBecomesTwoPieces) {
  const TetMesh mesh = kuhn_box(1, 1, 3, [](glm::dvec3 c) { return c.z < 1 || c.z > 2 ? 4 : 9; });
  const CoarseModel m = build_tet_model(mesh, nullptr);
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"label 4", "label 9", "label 4, part 2"}));
  EXPECT_EQ(count_pieces(m, 2), 6);
  EXPECT_EQ(m.surface.face_count(), 4u);
  EXPECT_EQ(validate(m.surface), "");
}

TEST(CoarseTetsErrors, ZeroVolumeTet) {
  TetMesh mesh = kuhn_box(1, 1, 1, [](glm::dvec3) { return 0; });
  mesh.vertices.emplace_back(0.5, 0.5, 0.0);
  mesh.tets.push_back({0, 1, 2, std::uint32_t(mesh.vertices.size() - 1)});
  mesh.labels.push_back(0);
  EXPECT_EQ(input_error([&] { build_tet_model(mesh, nullptr); }).rfind("tet mesh: tet 6: tetrahedron has zero volume", 0), 0u);
}

TEST(CoarseTetsErrors, CoincidentVerticesMakeZeroVolume) {
  TetMesh mesh;
  mesh.file = "m.mesh";
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e-14}};
  mesh.tets = {{0, 1, 2, 3}};
  mesh.labels = {0};
  mesh.tet_lines = {12};
  EXPECT_EQ(input_error([&] { build_tet_model(mesh, nullptr); }),
            "m.mesh:12: tetrahedron has zero volume: its vertices 0 and 3 coincide at (0, 0, 0)");
}

TEST(CoarseTetsErrors, IndexOutOfRangeNegativeLabelNoTets) {
  TetMesh mesh = kuhn_box(1, 1, 1, [](glm::dvec3) { return 0; });
  mesh.tets[2].z = 99;
  EXPECT_EQ(input_error([&] { build_tet_model(mesh, nullptr); }), "tet mesh: tet 2: vertex 99 is out of range (8 vertices)");
  mesh = kuhn_box(1, 1, 1, [](glm::dvec3) { return 0; });
  mesh.labels[4] = -1;
  EXPECT_EQ(input_error([&] { build_tet_model(mesh, nullptr); }), "tet mesh: tet 4: piece label -1 is negative");
  TetMesh empty;
  empty.file = "e.mesh";
  EXPECT_EQ(input_error([&] { build_tet_model(empty, nullptr); }), "e.mesh: the mesh has no tetrahedra");
}

TEST(CoarseTetsErrors, FaceSharedByThreeTets) {
  TetMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {0.2, 0.2, 2}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  mesh.labels = {0, 1, 2};
  const std::string e = input_error([&] { build_tet_model(mesh, nullptr); });
  EXPECT_NE(e.find("is shared by 3 tetrahedra (tet 0, tet 1 and tet 2)"), std::string::npos) << e;
}

TEST(CoarseTetsErrors, OverlappingTetsOnOneSideOfAFace) {
  TetMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.1, 0.1, 2}};
  mesh.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}};
  mesh.labels = {0, 0};
  const std::string e = input_error([&] { build_tet_model(mesh, nullptr); });
  EXPECT_NE(e.find("tet 1: tetrahedron overlaps tet 0"), std::string::npos) << e;
}

TEST(CoarseTetsErrors, UnknownMeshExtension) {
  EXPECT_EQ(input_error([] { load_tet_model("model.vtk", {}); }),
            "model.vtk: unknown tetrahedral mesh format '.vtk' (expected .mesh for MEDIT, .node or .ele for TetGen)");
}

}  // namespace
}  // namespace fracref
