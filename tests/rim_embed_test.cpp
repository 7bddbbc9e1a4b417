// S's rim embedded in B (issue 29), on hand-made cases that broke the old pieces stage: a rim
// edge crossing several B triangles is split where it crosses their edges; rim vertices on a B
// edge or a B vertex are located there exactly; two rim edges meet inside one B triangle; a fan
// that grazes a concave notch of B is trimmed to B; a rim edge across B's inside is traced round
// the side away from the sheet; a chord whose traces meet another face is bisected (issue 30).
// After each: S valid, every rim edge inside one triangle of B, every rim vertex at its location.
#include <gtest/gtest.h>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "pieces_test_support.hpp"
#include "rim/rim_on_b.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {
namespace {

using namespace pieces_test;
using rim::Location;

rim::ExteriorMesh unit_box(int n) { return rim::make_exterior_mesh(box(glm::dvec3(0.0), glm::dvec3(1.0), n)); }

// A k x k sheet spanning the unit box at height z (its rim on the box's four sides).
FractureSurface sheet_across(int k, double z) {
  return grid_sheet(k + 1, [k, z](int i, int j) { return glm::dvec3(double(i) / k, double(j) / k, z); });
}

// The rim vertex of S nearest to p.
std::uint32_t rim_vertex_at(const FractureSurface& s, const rim::RimOnB& rim, const glm::dvec3& p) {
  std::uint32_t best = rim::kNone;
  double d_best = 1e300;
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    if (!rim.on_b[v]) continue;
    const double d = glm::distance(glm::dvec3(glm::vec3(s.positions[v])), p);
    if (d < d_best) d_best = d, best = v;
  }
  EXPECT_LT(d_best, 1e-6) << "no rim vertex at " << rim::format_point(p);
  return best;
}

// What embed_rim promises, whatever the case.
void expect_embedded(const FractureSurface& s, const rim::ExteriorMesh& m, const rim::RimOnB& rim) {
  ASSERT_EQ(validate(s), "");
  EXPECT_EQ(rim::find_unembedded_rim(s, m, rim), "");
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    const bool boundary = (s.vertex_flags[v] & kVertexBoundary) != 0;
    EXPECT_EQ(bool(rim.on_b[v]), boundary) << "vertex " << v;
    if (rim.on_b[v]) {
      EXPECT_LT(glm::distance(glm::dvec3(glm::vec3(s.positions[v])), rim.at[v].point), 1e-6) << v;
    }
  }
}

// Points of every face of S (a barycentric lattice of `n` steps a side) lie inside B or on it.
void expect_inside(const FractureSurface& s, const rim::ExteriorMesh& m, int n = 8) {
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const glm::dvec3 a(glm::vec3(s.positions[s.faces[f].x])), b(glm::vec3(s.positions[s.faces[f].y])),
        c(glm::vec3(s.positions[s.faces[f].z]));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const glm::dvec3 p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        if (point_in_mesh(m.bvh, p)) continue;
        EXPECT_LT(closest_point(m.bvh, p).squared_distance, 1e-12) << "face " << f << " leaves B at " << rim::format_point(p);
      }
  }
}

}  // namespace

TEST(RimEmbed, RimEdgeCrossingSeveralTrianglesIsSplitAtTheirEdges) {
  const rim::ExteriorMesh m = unit_box(8);  // B's triangles 1/8 wide: each rim edge of 1/2 crosses several
  FractureSurface s = sheet_across(2, 0.53);
  const std::size_t before = s.positions.size();
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  EXPECT_GE(s.positions.size(), before + 8 * 4);  // four crossings or more per rim edge
  EXPECT_EQ(e.added.size(), s.positions.size() - before);
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    if (e.rim.on_b[v]) {
      const glm::dvec3 p(glm::vec3(s.positions[v]));
      EXPECT_LT(std::min({p.x, 1.0 - p.x, p.y, 1.0 - p.y}), 1e-6) << "rim vertex " << v << " off the box's sides";
    }
  expect_inside(s, m);
}

TEST(RimEmbed, RimVerticesOnBEdgesAndVerticesAreLocatedThere) {
  const rim::ExteriorMesh m = unit_box(2);  // B's vertices at 0, 1/2, 1 along each axis
  FractureSurface s = sheet_across(4, 0.5);  // its rim runs along B's edges at z = 1/2
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {0.0, 0.5, 0.5})].kind, Location::kVertex);
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {0.0, 0.0, 0.5})].kind, Location::kVertex);
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {0.0, 0.25, 0.5})].kind, Location::kEdge);
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {0.75, 1.0, 0.5})].kind, Location::kEdge);
  expect_inside(s, m);
}

// The refiner's slid rim: a rim vertex on a B edge whose float position lies a hair off it (here
// 1e-5 up, into the triangle above) is located in that triangle when located again, and keeps
// its edge when its location is given (EmbedOptions::known), moved back onto it.
TEST(RimEmbed, KnownLocationsAreKeptOverTheirFloatPositions) {
  const rim::ExteriorMesh m = unit_box(2);
  FractureSurface s = sheet_across(4, 0.5);
  const rim::Embedding first = rim::embed_rim(s, m);
  const std::uint32_t v = rim_vertex_at(s, first.rim, {0.0, 0.25, 0.5});
  ASSERT_EQ(first.rim.at[v].kind, Location::kEdge);
  FractureSurface nudged = s;
  nudged.positions[v].z += 1e-5f;
  FractureSurface again = nudged;
  EXPECT_EQ(rim::embed_rim(again, m).rim.at[v].kind, Location::kFace);
  rim::EmbedOptions o;
  o.known = &first.rim;
  FractureSurface kept = nudged;
  const rim::Embedding k = rim::embed_rim(kept, m, o);
  expect_embedded(kept, m, k.rim);
  EXPECT_EQ(k.rim.at[v].kind, Location::kEdge);
  EXPECT_EQ(k.rim.at[v].id, first.rim.at[v].id);
  EXPECT_EQ(glm::vec3(kept.positions[v]), glm::vec3(first.rim.at[v].point));
}

TEST(RimEmbed, TwoRimEdgesMeetInsideOneTriangle) {
  const rim::ExteriorMesh m = unit_box(1);  // two triangles a side
  FractureSurface s = sheet_across(2, 0.3);
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  // (0, 1/2, 0.3) is off the side's diagonal: inside one triangle, and both its rim edges end
  // in that triangle (the one crossing the diagonal is split there).
  const std::uint32_t v = rim_vertex_at(s, e.rim, {0.0, 0.5, 0.3});
  EXPECT_EQ(e.rim.at[v].kind, Location::kFace);
  std::size_t rim_edges = 0;
  for (std::size_t k = 0; k < s.edges.size(); ++k) {
    const glm::uvec2 ed = s.edges[k];
    if ((ed.x == v || ed.y == v) && s.ef_offsets[k + 1] - s.ef_offsets[k] == 1) {
      ++rim_edges;
      EXPECT_NE(rim::common_face(m, e.rim.at[ed.x], e.rim.at[ed.y]), rim::kNone);
    }
  }
  EXPECT_EQ(rim_edges, 2u);
  expect_inside(s, m);
}

// An L-shaped prism (cells (0,0), (1,0), (0,1); the notch (1,1) is a concave crease of B) and a
// fan of three faces whose rim vertex w0 sits on the notch's wall x = 1: the edge from w0 to the
// inner vertex crosses the notch, so S leaves B there. Trimmed, S lies inside B.
TEST(RimEmbed, FanGrazingAConcaveNotchIsTrimmedToB) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0));
  std::vector<glm::vec4> positions = {{1.0f, 1.05f, 0.5f, 1.0f}, {2.0f, 0.5f, 0.3f, 1.0f},
                                      {1.5f, 0.0f, 0.7f, 1.0f}, {1.5f, 0.5f, 0.5f, 1.0f}};
  const std::vector<glm::uvec4> faces = {{3, 0, 1, 0}, {3, 1, 2, 0}, {3, 2, 0, 0}};
  FractureSurface s = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(3, glm::ivec2(1, 0)), 2);
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  EXPECT_GT(e.trim.removed_faces, 0u);
  EXPECT_GT(e.trim.new_vertices, 0u);
  expect_inside(s, m, 16);
}

// A sheet at z = 1/2 that covers only the upper part of the unit box's section (y above about
// 1/2): its lower rim edge p-q runs straight across B's inside, from the wall x = 0 to the wall
// x = 1. Its face's plane meets B in the section's square; from p, the way along it that heads
// straightest for q is up the wall, round the rest of the sheet (its faces would fold over the
// sheet); the way that embeds S is the other one, down and round the lower part, which the face
// then covers (flat_split's second way). Before it, the face got the unchecked fan of traces at
// right angles to B, which also ran round the sheet: "fracture surface vertices 5 and 10 both
// lie on exterior vertex 17".
TEST(RimEmbed, ARimEdgeAcrossBIsTracedRoundTheSideAwayFromTheSheet) {
  const rim::ExteriorMesh m = unit_box(4);
  std::vector<glm::vec4> positions = {{0.0f, 0.5f, 0.5f, 1.0f}, {1.0f, 0.6f, 0.5f, 1.0f}, {1.0f, 1.0f, 0.5f, 1.0f},
                                      {0.0f, 1.0f, 0.5f, 1.0f}, {0.5f, 0.8f, 0.5f, 1.0f}};
  const std::vector<glm::uvec4> faces = {{0, 1, 4, 0}, {1, 2, 4, 0}, {2, 3, 4, 0}, {3, 0, 4, 0}};
  FractureSurface s = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(4, glm::ivec2(1, 0)), 2);
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  expect_inside(s, m);
  // The sheet now spans the whole section: its rim reaches the box's corners (0, 0) and (1, 0).
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {0.0, 0.0, 0.5})].kind, Location::kVertex);
  EXPECT_EQ(e.rim.at[rim_vertex_at(s, e.rim, {1.0, 0.0, 0.5})].kind, Location::kVertex);
  double area = 0.0;
  for (const glm::uvec4& f : s.faces) {
    const glm::dvec3 a(glm::vec3(s.positions[f.x])), b(glm::vec3(s.positions[f.y])), c(glm::vec3(s.positions[f.z]));
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  EXPECT_NEAR(area, 1.0, 1e-5);  // the unit square, each part once
}

// A sheet across the unit box's edge x = z = 0 (a fan around c, its rim on the wall x = 0 and the
// floor) and a small triangle G, a face of S of its own, that cuts the corner where the chord
// p-q's traces pass the edge (at right angles to B, and in the face's plane: c is in the plane of
// p, q and (0, 0.49, 0)): each split of face (c, p, q) along them meets G, and so does none
// better the other way round. Bisected at the point of B nearest the chord's middle (on the
// floor), the halves' traces pass the edge near y = 0.43, clear of G. Before the bisection, the
// face became the unchecked fan through G, and S met itself.
TEST(RimEmbed, AChordWhoseTracesMeetAnotherFaceIsBisected) {
  const rim::ExteriorMesh m = unit_box(4);
  std::vector<glm::vec4> positions = {{0.3f, 0.424f, 0.45f, 1.0f},  // c
                                      {0.0f, 0.3f, 0.5f, 1.0f},     // p
                                      {0.6f, 0.7f, 0.0f, 1.0f},     // q
                                      {0.7f, 0.95f, 0.0f, 1.0f},    {0.0f, 0.9f, 0.6f, 1.0f},
                                      {0.0f, 0.47f, 0.04f, 1.0f},   {0.04f, 0.49f, 0.0f, 1.0f},  // G
                                      {0.0f, 0.51f, 0.04f, 1.0f}};
  const std::vector<glm::uvec4> faces = {{0, 1, 2, 0}, {0, 2, 3, 0}, {0, 3, 4, 0}, {0, 4, 1, 0}, {5, 6, 7, 0}};
  FractureSurface s = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(5, glm::ivec2(1, 0)), 2);
  const rim::Embedding e = rim::embed_rim(s, m);
  expect_embedded(s, m, e.rim);
  expect_inside(s, m);
  std::vector<glm::dvec3> x;
  std::vector<TriangleIds> tris;
  for (const glm::vec4& p : s.positions) x.push_back(glm::dvec3(glm::vec3(p)));
  for (const glm::uvec4& f : s.faces) tris.push_back({f.x, f.y, f.z});
  EXPECT_TRUE(find_self_intersections(x, tris, 4).empty());
}

}  // namespace fracref
