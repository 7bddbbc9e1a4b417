// validate() on deliberately broken fracture surfaces: each case asserts the exact message, so a
// user reading it can find the broken index. Also make_fracture_surface's input errors.
#include <gtest/gtest.h>

#include <limits>
#include <utility>

#include "surface/fracture_surface.hpp"
#include "surface/surface_examples.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// example_sheet(3) numbers its lattice like this (the messages below name these ids):
//   y=2:  7 6 8          faces 0 (0 1 2)  1 (0 2 3)  2 (1 4 5)  3 (1 5 2)
//   y=1:  3 2 5                4 (3 2 6)  5 (3 6 7)  6 (2 5 8)  7 (2 8 6)
//   y=0:  0 1 4   (x = 0, 1, 2)
TEST(SurfaceValidate, LatticeNumberingUsedByTheseTests) {
  const FractureSurface s = example_sheet(3);
  const glm::vec2 at[9] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {2, 1}, {1, 2}, {0, 2}, {2, 2}};
  for (int v = 0; v < 9; ++v) EXPECT_EQ(glm::vec2(s.positions[v]), at[v]) << "vertex " << v;
  EXPECT_EQ(s.faces[4], glm::uvec4(3, 2, 6, 0));
  EXPECT_EQ(s.faces[5], glm::uvec4(3, 6, 7, 0));
  // The cross's junction runs through vertices 1 (0,0,0), 2 (0,1,0) and 4 (0,2,0); its faces
  // come in strips of 4: z = 0 left, z = 0 right, x = 0 up, x = 0 down.
  const FractureSurface c = example_cross(2);
  EXPECT_EQ(glm::vec3(c.positions[1]), glm::vec3(0, 0, 0));
  EXPECT_EQ(glm::vec3(c.positions[2]), glm::vec3(0, 1, 0));
  EXPECT_EQ(c.faces[0], glm::uvec4(0, 1, 2, 0));
  EXPECT_EQ(c.faces[13], glm::uvec4(12, 2, 1, 0));
}

TEST(SurfaceValidate, ExamplesAreValid) {
  EXPECT_EQ(validate(example_sheet(2)), "");
  EXPECT_EQ(validate(example_sheet(5, {{1, 1}, {3, 2}})), "");
  EXPECT_EQ(validate(example_t_junction(1)), "");
  EXPECT_EQ(validate(example_t_junction(7)), "");
  EXPECT_EQ(validate(example_cross(5)), "");
  EXPECT_EQ(validate(FractureSurface{}), "");
  EXPECT_NO_THROW(validate_or_throw(example_cross(2)));
}

// After rebuild_adjacency, validate_rebuilt gives validate's verdict without the second rebuild.
TEST(SurfaceValidate, RebuiltSurfacesGetValidatesVerdict) {
  FractureSurface s = example_cross(3);
  EXPECT_EQ(validate_rebuilt(s), "");
  s.face_pieces[0] = glm::ivec2(s.face_pieces[0].y, s.face_pieces[0].x);  // one face turned inside out
  rebuild_adjacency(s);
  ASSERT_NE(validate(s), "");
  EXPECT_EQ(validate_rebuilt(s), validate(s));
  FractureSurface t = example_sheet(3);
  t.faces[1] = t.faces[0];  // the same vertex set twice
  rebuild_adjacency(t);
  ASSERT_NE(validate(t), "");
  EXPECT_EQ(validate_rebuilt(t), validate(t));
}

TEST(SurfaceValidate, StaleVertexFacesAfterMovingAFaceIndex) {
  FractureSurface s = example_sheet(3);
  s.faces[0].y = 4;  // (0 1 2) -> (0 4 2): vertex 1 still lists face 0
  EXPECT_EQ(validate(s), "vertex 1: vf lists face 0 but face 0 does not use vertex 1");
  EXPECT_THROW(validate_or_throw(s), RunError);
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s), "");

  FractureSurface t = example_sheet(3);
  t.faces[7].y = 0;  // (2 8 6) -> (2 0 6): vertex 0 does not list face 7
  EXPECT_EQ(validate(t), "vertex 0: face 7 uses it but is missing from vf");
}

TEST(SurfaceValidate, StaleEdgeFaces) {
  FractureSurface s = example_sheet(3);
  ASSERT_EQ(s.edges[0], glm::uvec2(0, 1));
  s.ef_faces[s.ef_offsets[0]] = 5;
  EXPECT_EQ(validate(s), "edge 0-1: ef lists face 5 but face 5 has no such edge");
}

TEST(SurfaceValidate, StaleDerivedArrays) {
  const FractureSurface good = example_sheet(3);
  FractureSurface s = good;
  s.vf_offsets.pop_back();
  EXPECT_EQ(validate(s), "vf_offsets has 9 entries, expected 10 (vertices + 1)");
  s = good;
  s.edge_special[0] = kEdgeNonManifold;
  EXPECT_EQ(validate(s), "edge 0-1: marked non-manifold, expected boundary (1 face)");
  s = good;
  std::swap(s.side_component[0], s.side_component[1]);
  EXPECT_EQ(validate(s), "face 0 front side: component 1, expected 0");
  s = good;
  s.component_count = 3;
  EXPECT_EQ(validate(s), "component_count is 3, expected 2");
  s = good;
  s.copies[0].y = 5;
  EXPECT_EQ(validate(s), "vertex 0: copies (piece:local) (0:5 1:0), expected (0:0 1:0)");
  s = good;
  s.piece_vertex_counts[1] = 8;
  EXPECT_EQ(validate(s), "piece 1: piece_vertex_counts is 8, expected 9");
}

TEST(SurfaceValidate, InconsistentPieceLabelOnOneFace) {
  FractureSurface s = example_sheet(3);
  s.piece_count = 3;
  s.face_pieces[5].y = 2;  // below face 5 lies piece 0, like below every other face
  EXPECT_EQ(validate(s), "piece_vertex_counts has 2 entries, expected 3 (one per piece)");
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s),
            "side component 1 holds pieces 0 and 2: edge 3-6 joins face 4 back (piece 0) and face 5 back (piece 2)");
  EXPECT_EQ(component_pieces(s), (std::vector<int>{1, -1}));
}

// A flipped face moves its front to the other side of the sheet, so the side components (built
// from winding) catch it before the per-piece edge check would.
TEST(SurfaceValidate, FlippedWindingWithoutSwappingPieces) {
  FractureSurface s = example_sheet(3);
  std::swap(s.faces[5].y, s.faces[5].z);  // (3 6 7) -> (3 7 6)
  const std::string stale = validate(s);
  EXPECT_EQ(stale.rfind("face 5: face_edges[0] is ", 0), 0u) << stale;
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s),
            "side component 0 holds pieces 0 and 1: edge 3-6 joins face 4 front (piece 1) and face 5 back (piece 0)");
  std::swap(s.face_pieces[5].x, s.face_pieces[5].y);  // flipping the labels too makes it valid
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s), "");
}

// A piece on both sides of a crossing (two opposite quadrants) would have a non-manifold mesh.
TEST(SurfaceValidate, PieceTouchingItselfAcrossAJunction) {
  FractureSurface s = example_cross(2);
  const glm::ivec2 strips[4] = {{0, 2}, {1, 0}, {1, 0}, {0, 2}};  // left, right, up, down
  for (std::size_t f = 0; f < s.faces.size(); ++f) s.face_pieces[f] = strips[f / 4];
  s.piece_count = 3;
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s), "piece 0: edge 1-2 used by its outward faces in the same direction twice");
}

// Labels that each make a clean sheet but claim overlapping regions: only the geometric (radial)
// side components see that the quadrant below-left is labelled both 1 and 3.
TEST(SurfaceValidate, CrossLabelledAsTwoIndependentSheets) {
  FractureSurface s = example_cross(2);
  for (std::size_t f = 0; f < s.faces.size(); ++f) s.face_pieces[f] = f < 8 ? glm::ivec2(0, 1) : glm::ivec2(2, 3);
  rebuild_adjacency(s);
  EXPECT_EQ(validate(s),
            "side component 1 holds pieces 1 and 3: edge 1-2 joins face 13 back (piece 3) and face 0 back (piece 1)");
}

TEST(SurfaceValidate, WrongVertexFlags) {
  const FractureSurface sheet = example_sheet(3);
  FractureSurface s = sheet;
  s.vertex_flags[0] &= ~kVertexBoundary;
  EXPECT_EQ(validate(s), "vertex 0: on boundary edge 0-1 but not flagged boundary");
  s = sheet;
  s.vertex_flags[2] |= kVertexBoundary;
  EXPECT_EQ(validate(s), "vertex 2: flagged boundary but on no boundary edge");
  s = sheet;
  s.vertex_flags[4] |= kVertexNonManifold;
  EXPECT_EQ(validate(s), "vertex 4: flagged non-manifold but on no non-manifold edge and not a pinch vertex");
  s = sheet;
  s.vertex_flags[3] |= 8;
  EXPECT_EQ(validate(s), "vertex 3: unknown flag bits 8");

  FractureSurface t = example_t_junction(2);
  ASSERT_EQ(glm::vec3(t.positions[2]), glm::vec3(0, 1, 0));
  t.vertex_flags[2] &= ~kVertexNonManifold;
  EXPECT_EQ(validate(t), "vertex 2: on non-manifold edge 1-2 but not flagged non-manifold");

  FractureSurface pinch = make_fracture_surface(
      {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {-1, 0, 0, 1}, {0, -1, 0, 1}}, {{0, 1, 2, 0}, {0, 3, 4, 0}},
      {{1, 0}, {1, 0}}, 2);
  pinch.vertex_flags[0] &= ~kVertexNonManifold;
  EXPECT_EQ(validate(pinch), "vertex 0: pinch vertex (its faces form 2 fans) but not flagged non-manifold");
}

TEST(SurfaceValidate, BrokenPrimaryData) {
  const FractureSurface sheet = example_sheet(3);
  FractureSurface s = sheet;
  s.faces[3].y = 99;
  EXPECT_EQ(validate(s), "face 3: vertex 99 out of range (9 vertices)");
  s = sheet;
  s.faces.push_back({0, 2, 1, 0});
  s.face_pieces.push_back({0, 1});
  EXPECT_EQ(validate(s), "face 8: duplicate of face 0 (vertices 0 2 1)");
  s = sheet;
  s.faces[6].z = 5;
  EXPECT_EQ(validate(s), "face 6: repeats a vertex (2 5 5)");
  s = sheet;
  s.face_pieces[2] = {1, 1};
  EXPECT_EQ(validate(s), "face 2: front and back are the same piece 1");
  s = sheet;
  s.face_pieces[2].y = 2;
  EXPECT_EQ(validate(s), "face 2: back piece 2 out of range (2 pieces)");
  s = sheet;
  s.positions[4].x = std::numeric_limits<float>::infinity();
  EXPECT_EQ(validate(s), "vertex 4: position (inf, 0, 0) is not finite");
  s = sheet;
  s.positions[1].w = 0.0f;
  EXPECT_EQ(validate(s), "vertex 1: position w is 0, expected 1");
  s = sheet;
  s.face_pieces.pop_back();
  EXPECT_EQ(validate(s), "face_pieces has 7 entries, expected 8 (one per face)");
  s = sheet;
  s.faces[7].w = 3;
  EXPECT_EQ(validate(s), "face 7: w is 3, expected 0");
}

std::string make_error(std::vector<glm::vec4> positions, std::vector<glm::uvec4> faces,
                       std::vector<glm::ivec2> pieces, int piece_count) {
  try {
    make_fracture_surface(std::move(positions), std::move(faces), std::move(pieces), piece_count);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

// On a surface large enough that the duplicate search runs beside the later checks, a duplicate
// face is still reported before them (the appended face also leaves the derived arrays stale),
// and without it the later checks still find a stale array.
TEST(SurfaceValidate, LargeSurfaceReportsTheDuplicateFirst) {
  const FractureSurface sheet = example_sheet(80);
  ASSERT_GT(sheet.faces.size(), 10000u);
  FractureSurface s = sheet;
  const glm::uvec4 f = s.faces[5];
  s.faces.push_back({f.y, f.z, f.x, 0});
  s.face_pieces.push_back(s.face_pieces[5]);
  EXPECT_EQ(validate(s), "face " + std::to_string(sheet.faces.size()) + ": duplicate of face 5 (vertices " +
                             std::to_string(f.y) + " " + std::to_string(f.z) + " " + std::to_string(f.x) + ")");
  EXPECT_EQ(validate_rebuilt(s).substr(0, 5), "face ");
  s = sheet;
  s.edge_special[0] = kEdgeNonManifold;
  EXPECT_NE(validate(s), "");
  EXPECT_EQ(validate(sheet), "");
}

TEST(SurfaceMake, InputErrorsNameTheFaceOrVertex) {
  const std::vector<glm::vec4> quad = {{0, 0, 0, 1}, {1, 0, 0, 1}, {1, 1, 0, 1}, {0, 1, 0, 1}};
  const std::vector<glm::ivec2> pieces = {{1, 0}, {1, 0}};
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}, {0, 2, 7, 0}}, pieces, 2), "face 1: vertex 7 out of range (4 vertices)");
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}, {0, 2, 0, 0}}, pieces, 2), "face 1: repeats a vertex (0 2 0)");
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}, {0, 2, 3, 0}}, {{1, 0}, {1, 1}}, 2),
            "face 1: front and back are the same piece 1");
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}, {0, 2, 3, 0}}, {{-1, 0}, {1, 0}}, 2),
            "face 0: front piece -1 out of range (2 pieces)");
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}, {1, 2, 0, 0}}, pieces, 2), "face 1: duplicate of face 0 (vertices 1 2 0)");
  EXPECT_EQ(make_error(quad, {{0, 1, 2, 0}}, pieces, 2), "face_pieces has 2 entries, expected 1 (one per face)");
  std::vector<glm::vec4> bad = quad;
  bad[2].y = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(make_error(bad, {{0, 1, 2, 0}, {0, 2, 3, 0}}, pieces, 2), "vertex 2: position (1, -inf, 0) is not finite");
}

TEST(SurfaceMake, NormalisesWAndMarksVerticesOriginal) {
  const FractureSurface s = make_fracture_surface({{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 7}}, {{0, 1, 2, 9}}, {{0, 1}}, 2);
  EXPECT_EQ(s.positions[2].w, 1.0f);
  EXPECT_EQ(s.faces[0].w, 0u);
  EXPECT_EQ(s.vertex_flags[0], kVertexBoundary | kVertexOriginal);
  EXPECT_EQ(validate(s), "");
}

}  // namespace
}  // namespace fracref
