// The fracture surface's derived topology on hand-built shapes with known counts: sheet, sheet
// with a hole, T-junction, cross, pinch vertex; per-piece meshes and their orientation.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "surface/fracture_surface.hpp"
#include "surface/surface_examples.hpp"
#include "util/error.hpp"
#include "surface_test_support.hpp"

namespace fracref {
namespace {

std::uint32_t vertex_at(const FractureSurface& s, glm::vec3 p) {
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    if (glm::vec3(s.positions[v]) == p) return v;
  ADD_FAILURE() << "no vertex at " << p.x << " " << p.y << " " << p.z;
  return kNoEdge;
}

std::size_t count_edges(const FractureSurface& s, EdgeKind kind) {
  return std::size_t(std::count(s.edge_special.begin(), s.edge_special.end(), std::uint8_t(kind)));
}

std::size_t count_flag(const FractureSurface& s, std::uint32_t bit) {
  return std::size_t(std::count_if(s.vertex_flags.begin(), s.vertex_flags.end(), [&](std::uint32_t f) { return f & bit; }));
}

std::uint32_t copy_count(const FractureSurface& s, std::uint32_t v) { return s.copy_offsets[v + 1] - s.copy_offsets[v]; }

std::uint32_t ef_count(const FractureSurface& s, std::uint32_t e) { return s.ef_offsets[e + 1] - s.ef_offsets[e]; }

glm::vec3 normal(const PieceMesh& m, std::size_t t) {
  const glm::vec3 a = m.positions[m.triangles[t].x], b = m.positions[m.triangles[t].y], c = m.positions[m.triangles[t].z];
  return glm::normalize(glm::cross(b - a, c - a));
}

// Every piece's component(s) carry that piece only, and every piece owns at least one.
void expect_components_match_pieces(const FractureSurface& s) {
  const std::vector<int> pieces = component_pieces(s);
  for (std::uint32_t side = 0; side < s.side_component.size(); ++side)
    EXPECT_EQ(pieces[s.side_component[side]], side_piece(s, side)) << "side " << side;
  EXPECT_EQ(std::set<int>(pieces.begin(), pieces.end()).size(), std::size_t(s.piece_count));
}

// The rounding must happen in an optimised build too: GCC 12.2 compiled dvec3(vec3(p)) to return
// x and y unrounded (see stored_position).
TEST(StoredPosition, RoundsEachCoordinateToFloat) {
  volatile double in[3] = {0x1.fa5137d315a8fp-2, 0x1.3416fe12345p-1, -0x1.99eb3abcdefp-1};
  const glm::dvec3 p(in[0], in[1], in[2]);
  const glm::dvec3 q = stored_position(p);
  for (int k = 0; k < 3; ++k) {
    volatile float f = float(p[k]);
    EXPECT_EQ(q[k], double(f)) << "coordinate " << k;
    EXPECT_NE(q[k], p[k]) << "coordinate " << k;
  }
}

TEST(SurfaceSheet, ThreeByThreeGridSplitsTwoPieces) {
  const FractureSurface s = example_sheet(3);
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(s.positions.size(), 9u);
  EXPECT_EQ(s.faces.size(), 8u);
  EXPECT_EQ(s.edges.size(), 16u);
  EXPECT_EQ(count_edges(s, kEdgeBoundary), 8u);
  EXPECT_EQ(count_edges(s, kEdgeRegular), 8u);
  EXPECT_EQ(count_edges(s, kEdgeNonManifold), 0u);
  EXPECT_EQ(s.component_count, 2u);
  EXPECT_EQ(count_flag(s, kVertexBoundary), 8u);
  EXPECT_EQ(count_flag(s, kVertexNonManifold), 0u);
  EXPECT_EQ(count_flag(s, kVertexOriginal), 9u);
  const std::uint32_t center = vertex_at(s, {1, 1, 0});
  EXPECT_EQ(s.vertex_flags[center], std::uint32_t(kVertexOriginal));
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    EXPECT_EQ(s.side_component[2 * f], 0u);
    EXPECT_EQ(s.side_component[2 * f + 1], 1u);
  }
  // Both pieces hold every vertex, numbered as in S.
  for (std::uint32_t v = 0; v < 9; ++v) {
    ASSERT_EQ(copy_count(s, v), 2u);
    EXPECT_EQ(s.copies[s.copy_offsets[v]], glm::uvec2(0, v));
    EXPECT_EQ(s.copies[s.copy_offsets[v] + 1], glm::uvec2(1, v));
  }
  EXPECT_EQ(s.piece_vertex_counts, (std::vector<std::uint32_t>{9, 9}));
  expect_components_match_pieces(s);
}

TEST(SurfaceSheet, CsrListsAreSortedAndConsistent) {
  const FractureSurface s = example_sheet(3);
  const std::uint32_t center = vertex_at(s, {1, 1, 0});
  // The centre vertex touches 6 faces (a grid with one diagonal direction); corners 1 or 2.
  EXPECT_EQ(s.vf_offsets[center + 1] - s.vf_offsets[center], 6u);
  EXPECT_TRUE(std::is_sorted(s.vf_faces.begin() + s.vf_offsets[center], s.vf_faces.begin() + s.vf_offsets[center + 1]));
  for (std::size_t e = 1; e < s.edges.size(); ++e) {
    EXPECT_LT(s.edges[e - 1].x * 100 + s.edges[e - 1].y, s.edges[e].x * 100 + s.edges[e].y);
    EXPECT_LT(s.edges[e].x, s.edges[e].y);
  }
  for (std::uint32_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t e = s.face_edges[3 * f + i];
      EXPECT_EQ(e, find_edge(s, s.faces[f][i], s.faces[f][(i + 1) % 3]));
    }
  EXPECT_EQ(find_edge(s, vertex_at(s, {0, 0, 0}), vertex_at(s, {2, 2, 0})), kNoEdge);
}

// The vertex-face lists and the edge table of a surface large enough for their two-thread build
// (and with non-manifold edges, so buckets hold edges of 1, 2 and 4 faces), against a reference
// built with an ordered map.
TEST(SurfaceRebuild, LargeTablesMatchAPlainReference) {
  const FractureSurface s = example_cross(3000);
  ASSERT_GT(s.faces.size(), 20000u);
  std::vector<std::vector<std::uint32_t>> vf(s.positions.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> ef;
  for (std::uint32_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = s.faces[f][i], b = s.faces[f][(i + 1) % 3];
      vf[a].push_back(f);
      ef[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    ASSERT_EQ(std::vector<std::uint32_t>(s.vf_faces.begin() + s.vf_offsets[v], s.vf_faces.begin() + s.vf_offsets[v + 1]),
              vf[v]) << "vertex " << v;
  ASSERT_EQ(s.edges.size(), ef.size());
  std::uint32_t e = 0;
  for (const auto& [ab, faces] : ef) {
    ASSERT_EQ(s.edges[e], glm::uvec2(ab.first, ab.second)) << "edge " << e;
    ASSERT_EQ(std::vector<std::uint32_t>(s.ef_faces.begin() + s.ef_offsets[e], s.ef_faces.begin() + s.ef_offsets[e + 1]),
              faces) << "edge " << e;
    const std::uint8_t kind = faces.size() == 1 ? kEdgeBoundary : faces.size() == 2 ? kEdgeRegular : kEdgeNonManifold;
    ASSERT_EQ(s.edge_special[e], kind) << "edge " << e;
    ++e;
  }
  for (std::uint32_t f = 0; f < s.faces.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = s.faces[f][i], b = s.faces[f][(i + 1) % 3];
      ASSERT_EQ(s.edges[s.face_edges[3 * f + i]], glm::uvec2(std::min(a, b), std::max(a, b))) << "face " << f;
    }
}

TEST(SurfaceSheet, HoleLeavesAnInnerBoundaryLoop) {
  const FractureSurface s = example_sheet(6, {{2, 2}});
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(s.positions.size(), 36u);
  EXPECT_EQ(s.faces.size(), 48u);
  EXPECT_EQ(s.edges.size(), 84u);  // 85 grid edges less the hole's diagonal
  EXPECT_EQ(count_edges(s, kEdgeBoundary), 24u);  // 20 outer + 4 inner
  EXPECT_EQ(count_edges(s, kEdgeRegular), 60u);
  EXPECT_EQ(count_edges(s, kEdgeNonManifold), 0u);
  EXPECT_EQ(count_flag(s, kVertexBoundary), 24u);
  for (glm::vec3 p : {glm::vec3(2, 2, 0), glm::vec3(3, 2, 0), glm::vec3(3, 3, 0), glm::vec3(2, 3, 0)}) {
    const std::uint32_t v = vertex_at(s, p);
    EXPECT_EQ(s.vertex_flags[v], kVertexBoundary | kVertexOriginal);
    EXPECT_EQ(copy_count(s, v), 2u);
  }
  EXPECT_EQ(s.vertex_flags[vertex_at(s, {1, 1, 0})], std::uint32_t(kVertexOriginal));
  EXPECT_EQ(s.component_count, 2u);
  expect_components_match_pieces(s);
}

TEST(SurfaceTJunction, ThreePiecesMeetAlongALine) {
  const FractureSurface s = example_t_junction(2);
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(s.positions.size(), 12u);
  EXPECT_EQ(s.faces.size(), 12u);
  EXPECT_EQ(s.edges.size(), 23u);
  EXPECT_EQ(count_edges(s, kEdgeBoundary), 12u);
  EXPECT_EQ(count_edges(s, kEdgeRegular), 9u);
  EXPECT_EQ(count_edges(s, kEdgeNonManifold), 2u);
  EXPECT_EQ(s.component_count, 3u);
  EXPECT_EQ(count_flag(s, kVertexBoundary), 11u);
  EXPECT_EQ(count_flag(s, kVertexNonManifold), 3u);
  for (int y = 0; y <= 2; ++y) {
    const std::uint32_t v = vertex_at(s, glm::vec3(0, y, 0));
    EXPECT_TRUE(s.vertex_flags[v] & kVertexNonManifold);
    EXPECT_EQ(copy_count(s, v), 3u);
    if (y < 2) {
      const std::uint32_t e = find_edge(s, v, vertex_at(s, glm::vec3(0, y + 1, 0)));
      ASSERT_NE(e, kNoEdge);
      EXPECT_EQ(ef_count(s, e), 3u);
      EXPECT_EQ(s.edge_special[e], kEdgeNonManifold);
    }
  }
  EXPECT_EQ(s.vertex_flags[vertex_at(s, {0, 1, 0})], kVertexNonManifold | kVertexOriginal);
  EXPECT_EQ(copy_count(s, vertex_at(s, {-1, 1, 0})), 2u);
  EXPECT_EQ(copy_count(s, vertex_at(s, {0, 1, 1})), 2u);
  EXPECT_EQ(s.piece_vertex_counts, (std::vector<std::uint32_t>{9, 9, 9}));
  expect_components_match_pieces(s);
}

TEST(SurfaceCross, FourPiecesAroundALine) {
  const FractureSurface s = example_cross(2);
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(s.positions.size(), 15u);
  EXPECT_EQ(s.faces.size(), 16u);
  EXPECT_EQ(s.edges.size(), 30u);
  EXPECT_EQ(count_edges(s, kEdgeBoundary), 16u);
  EXPECT_EQ(count_edges(s, kEdgeRegular), 12u);
  EXPECT_EQ(count_edges(s, kEdgeNonManifold), 2u);
  EXPECT_EQ(s.component_count, 4u);
  EXPECT_EQ(count_flag(s, kVertexBoundary), 14u);
  EXPECT_EQ(count_flag(s, kVertexNonManifold), 3u);
  for (int y = 0; y <= 2; ++y) EXPECT_EQ(copy_count(s, vertex_at(s, glm::vec3(0, y, 0))), 4u);
  const std::uint32_t e = find_edge(s, vertex_at(s, {0, 0, 0}), vertex_at(s, {0, 1, 0}));
  ASSERT_NE(e, kNoEdge);
  EXPECT_EQ(ef_count(s, e), 4u);
  EXPECT_EQ(s.piece_vertex_counts, (std::vector<std::uint32_t>{9, 9, 9, 9}));
  expect_components_match_pieces(s);
}

// The radial order is geometric: rotating and shearing the whole surface, or leaning one sheet,
// must not change which sides face the same region.
TEST(SurfaceCross, ComponentsSurviveRotationAndLeaning) {
  const FractureSurface base = example_cross(3);
  FractureSurface s = base;
  const glm::mat3 r = glm::mat3(0.36f, 0.48f, -0.8f, -0.8f, 0.6f, 0.0f, 0.48f, 0.64f, 0.6f);  // a rotation
  for (glm::vec4& p : s.positions) p = glm::vec4(r * glm::vec3(p) + glm::vec3(5, -2, 7), 1.0f);
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s), "");
  EXPECT_EQ(s.side_component, base.side_component);
  FractureSurface leaning = base;
  for (glm::vec4& p : leaning.positions)
    if (p.z > 0.5f) p.x += 0.8f;  // the upper vertical sheet leans over the right piece
  rebuild_adjacency(leaning);
  EXPECT_EQ(validate(leaning), "");
  EXPECT_EQ(leaning.side_component, base.side_component);
}

TEST(SurfacePinch, TwoTrianglesSharingOnlyAVertex) {
  const FractureSurface s = make_fracture_surface(
      {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {-1, 0, 0, 1}, {0, -1, 0, 1}}, {{0, 1, 2, 0}, {0, 3, 4, 0}},
      {{1, 0}, {1, 0}}, 2);
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(s.vertex_flags[0], kVertexBoundary | kVertexNonManifold | kVertexOriginal);
  EXPECT_EQ(s.vertex_flags[1], kVertexBoundary | kVertexOriginal);
  EXPECT_EQ(count_edges(s, kEdgeBoundary), 6u);
  EXPECT_EQ(s.component_count, 4u);  // nothing joins across boundary edges
}

TEST(SurfacePieceMesh, SheetPiecesAreOrientedOutward) {
  const FractureSurface s = example_sheet(3);
  const PieceMesh below = piece_mesh(s, 0), above = piece_mesh(s, 1);
  ASSERT_EQ(below.triangles.size(), 8u);
  ASSERT_EQ(above.triangles.size(), 8u);
  for (std::size_t t = 0; t < 8; ++t) {
    EXPECT_EQ(normal(below, t), glm::vec3(0, 0, 1));  // the piece below looks up and out
    EXPECT_EQ(normal(above, t), glm::vec3(0, 0, -1));
  }
  EXPECT_THROW(piece_mesh(s, 2), RunError);
  EXPECT_THROW(piece_mesh(s, -1), RunError);
}

TEST(SurfacePieceMesh, TJunctionPieceMatchesCopiesAndIsOutward) {
  const FractureSurface s = example_t_junction(2);
  const PieceMesh m = piece_mesh(s, 1);  // above, x < 0
  ASSERT_EQ(m.triangles.size(), 8u);
  ASSERT_EQ(m.positions.size(), 9u);
  EXPECT_TRUE(std::is_sorted(m.vertex_to_canonical.begin(), m.vertex_to_canonical.end()));
  for (std::uint32_t i = 0; i < m.vertex_to_canonical.size(); ++i) {
    const std::uint32_t v = m.vertex_to_canonical[i];
    const auto b = s.copies.begin() + s.copy_offsets[v], e = s.copies.begin() + s.copy_offsets[v + 1];
    EXPECT_NE(std::find(b, e, glm::uvec2(1, i)), e) << "vertex " << v;
    EXPECT_EQ(m.positions[i], glm::vec3(s.positions[v]));
  }
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::vec3 n = normal(m, t);
    const bool vertical = m.positions[m.triangles[t].x].x == 0.0f && m.positions[m.triangles[t].y].x == 0.0f &&
                          m.positions[m.triangles[t].z].x == 0.0f;
    EXPECT_EQ(n, vertical ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, -1)) << "triangle " << t;
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE(directed.emplace(m.triangles[t][i], m.triangles[t][(i + 1) % 3]).second) << "triangle " << t;
  }
}

TEST(SurfaceRebuild, DeterministicAndIdempotent) {
  const FractureSurface a = example_cross(4);
  FractureSurface b = a;
  rebuild_adjacency(b);
  rebuild_adjacency(b);
  test::expect_same_derived(a, b);
}

TEST(SurfaceRebuild, KeepsOriginalFlagAndRecomputesTheRest) {
  FractureSurface s = example_sheet(3);
  const std::uint32_t center = vertex_at(s, {1, 1, 0});
  s.vertex_flags[center] = kVertexBoundary | kVertexNonManifold;  // stale bits, original lost
  rebuild_adjacency(s);
  EXPECT_EQ(s.vertex_flags[center], 0u);
  EXPECT_EQ(validate(s), "");
}

// A topology edit appends a vertex and a face and leaves vertex_flags short: rebuild fills it in.
TEST(SurfaceRebuild, AppendedVertexIsNotOriginal) {
  FractureSurface s = example_sheet(3);
  const std::uint32_t a = vertex_at(s, {0, 0, 0}), b = vertex_at(s, {1, 0, 0});
  s.positions.push_back({0.5f, -1.0f, 0.0f, 1.0f});
  s.faces.push_back({a, 9, b, 0});  // normal +z, like the rest of the sheet
  s.face_pieces.push_back({1, 0});
  rebuild_adjacency(s);
  ASSERT_EQ(validate(s), "");
  ASSERT_EQ(s.vertex_flags.size(), 10u);
  EXPECT_EQ(s.vertex_flags[9], std::uint32_t(kVertexBoundary));
  EXPECT_EQ(s.edge_special[find_edge(s, a, b)], kEdgeRegular);
  EXPECT_EQ(s.piece_vertex_counts, (std::vector<std::uint32_t>{10, 10}));
  EXPECT_EQ(s.component_count, 2u);
}

TEST(SurfaceRebuild, RejectsOutOfRangeIndices) {
  FractureSurface s = example_sheet(3);
  s.faces[1].z = 40;
  EXPECT_THROW(rebuild_adjacency(s), RunError);
  s.faces[1].z = 2;
  s.face_pieces[1].y = 7;
  EXPECT_THROW(rebuild_adjacency(s), RunError);
}

}  // namespace
}  // namespace fracref
