// Pre-fractured pieces: matching cut faces into S, the hull, welding, orientation, and the
// errors for open, overlapping and non-conforming pieces.
#include <gtest/gtest.h>

#include <cstdio>

#include "coarse/coarse_model.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {
using test::input_error;

// An axis-aligned box as OBJ text: 8 `v` lines and 6 outward quads (indices after `base`).
// `triangles` writes each quad as two triangles split along the diagonal from its first corner.
std::string obj_box(const std::string& name, glm::dvec3 lo, glm::dvec3 hi, int base, bool triangles = false,
                    bool inward = false) {
  std::string s = name.empty() ? "" : "o " + name + "\n";
  char line[160];
  for (int k = 0; k < 8; ++k) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    s += line;
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    int c[4] = {q[0], q[1], q[2], q[3]};
    if (inward) std::swap(c[1], c[3]);
    for (int& x : c) x += base + 1;
    if (triangles) {
      std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", c[0], c[1], c[2], c[0], c[2], c[3]);
    } else {
      std::snprintf(line, sizeof line, "f %d %d %d %d\n", c[0], c[1], c[2], c[3]);
    }
    s += line;
  }
  return s;
}

TEST(CoarsePieces, TwoCubesSharingAFaceInOneObj) {
  const test::TempDir dir;
  const auto obj = dir.file("pieces.obj", obj_box("left", {0, 0, 0}, {1, 1, 1}, 0) + obj_box("right", {1, 0, 0}, {2, 1, 1}, 8));
  const CoarseModel m = load_pieces(obj);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(m.surface.face_count(), 2u);  // the shared quad, split in 2 triangles
  EXPECT_EQ(m.surface.vertex_count(), 4u);
  EXPECT_EQ(m.vertices.size(), 16u);  // every piece keeps its own copy of the cut vertices
  EXPECT_EQ(m.hull.size(), 20u);
  EXPECT_TRUE(m.tets.empty());
  EXPECT_EQ(m.inverted_fixed, 0u);
  EXPECT_EQ(test::count_edges(m.surface, kEdgeBoundary), 4);
  for (std::size_t f = 0; f < 2; ++f) {
    EXPECT_EQ(m.surface.face_pieces[f], glm::ivec2(1, 0));
    const glm::vec4 a = m.surface.positions[m.surface.faces[f].x], b = m.surface.positions[m.surface.faces[f].y],
                    c = m.surface.positions[m.surface.faces[f].z];
    EXPECT_GT(glm::cross(glm::vec3(b - a), glm::vec3(c - a)).x, 0.0f);  // into the right piece
    EXPECT_EQ(a.x, 1.0f);
  }
  // Each piece sees S through its own vertices.
  for (std::uint32_t s = 0; s < 4; ++s) {
    ASSERT_EQ(m.surface.copy_offsets[s + 1] - m.surface.copy_offsets[s], 2u);
    const std::uint32_t k = m.surface.copy_offsets[s];
    EXPECT_LT(m.surface_copy_model_vertex[k], 8u);
    EXPECT_GE(m.surface_copy_model_vertex[k + 1], 8u);
    EXPECT_EQ(m.vertex_weld[m.surface_copy_model_vertex[k + 1]], m.surface_copy_model_vertex[k]);
  }
  int left_hull = 0;
  for (int p : m.hull_piece) left_hull += p == 0;
  EXPECT_EQ(left_hull, 10);
}

TEST(CoarsePieces, TrianglesFilesAndTinyOffsets) {
  // One file per piece, triangles, the right cube's positions off by 1e-12 (welded).
  const test::TempDir dir;
  const auto a = dir.file("a.obj", obj_box("", {0, 0, 0}, {1, 1, 1}, 0, true));
  const auto b = dir.file("b.obj", obj_box("", {1 + 1e-12, 0, 0}, {2, 1, 1 - 1e-12}, 0, true));
  const CoarseModel m = load_pieces(std::vector<std::filesystem::path>{a, b});
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"a.obj", "b.obj"}));
  EXPECT_EQ(m.surface.face_count(), 2u);
  EXPECT_EQ(m.hull.size(), 20u);
}

TEST(CoarsePieces, InsideOutPieceIsReversedAndCounted) {
  const test::TempDir dir;
  const auto obj = dir.file("p.obj", obj_box("a", {0, 0, 0}, {1, 1, 1}, 0) + obj_box("b", {1, 0, 0}, {2, 1, 1}, 8, false, true));
  const CoarseModel m = load_pieces(obj);
  EXPECT_EQ(m.inverted_fixed, 1u);
  EXPECT_EQ(m.surface.face_count(), 2u);
  EXPECT_EQ(validate(m.surface), "");
}

TEST(CoarsePieces, ThreePiecesMeetAtAJunction) {
  // A bottom slab and two cubes on it, each cube exactly on one half of the slab's top, which
  // is cut in two quads to conform.
  const test::TempDir dir;
  std::string s = "o bottom\n";
  for (double x : {0.0, 1.0, 2.0})
    for (double y : {0.0, 1.0})
      for (double z : {0.0, 1.0}) s += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  // vertex (x, y, z) -> 1 + 4*x + 2*y + z
  s += "f 1 3 7 5\nf 5 7 11 9\n";           // bottom z = 0 (two quads, outward -z)
  s += "f 2 6 8 4\nf 6 10 12 8\n";          // top z = 1 (outward +z), split at x = 1
  s += "f 1 5 6 2\nf 5 9 10 6\n";           // y = 0
  s += "f 3 4 8 7\nf 7 8 12 11\n";          // y = 1
  s += "f 1 2 4 3\nf 9 11 12 10\n";         // x = 0 and x = 2
  s += obj_box("left", {0, 0, 1}, {1, 1, 2}, 12) + obj_box("right", {1, 0, 1}, {2, 1, 2}, 20);
  const CoarseModel m = load_pieces(dir.file("three.obj", s));
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.surface.face_count(), 6u);  // two top quads of the slab, the wall between the cubes
  EXPECT_EQ(test::count_edges(m.surface, kEdgeNonManifold), 1);
  // slab: 10 quads less the 2 on top; each cube: 6 quads less its bottom and the wall.
  EXPECT_EQ(m.hull.size(), 16u + 8u + 8u);
}

TEST(CoarsePiecesErrors, NonConformingBigFaceAgainstTwoSmallCubes) {
  const test::TempDir dir;
  const auto obj = dir.file("nc.obj", obj_box("big", {0, 0, 0}, {2, 2, 1}, 0) + obj_box("small_a", {0.5, 0, 1}, {1.5, 1, 2}, 8) +
                                          obj_box("small_b", {0.5, 1, 1}, {1.5, 2, 2}, 16));
  const std::string e = input_error([&] { load_pieces(obj); });
  EXPECT_EQ(e.rfind(obj.string() + ": pieces 'big' and 'small_", 0), 0u) << e;
  EXPECT_NE(e.find("do not conform: face 1 of 'big'"), std::string::npos) << e;
  EXPECT_NE(e.find("without matching it vertex for vertex (a T-junction or a partial overlap)"), std::string::npos) << e;
}

TEST(CoarsePiecesErrors, TJunctionOfCutEdges) {
  // The right cube is split in two halves along y: the left cube's face x = 1 is one quad, the
  // halves give two: a T-junction in the cut.
  const test::TempDir dir;
  const auto obj = dir.file("t.obj", obj_box("left", {0, 0, 0}, {1, 1, 1}, 0) + obj_box("half_a", {1, 0, 0}, {2, 0.5, 1}, 8) +
                                         obj_box("half_b", {1, 0.5, 0}, {2, 1, 1}, 16));
  const std::string e = input_error([&] { load_pieces(obj); });
  EXPECT_NE(e.find(": pieces 'left' and 'half_"), std::string::npos) << e;
  EXPECT_NE(e.find("do not conform"), std::string::npos) << e;
}

TEST(CoarsePiecesErrors, OpenOverlappingAndUngroupedPieces) {
  const test::TempDir dir;
  std::string open = obj_box("a", {0, 0, 0}, {1, 1, 1}, 0);
  open = open.substr(0, open.rfind("f "));  // drop the last quad
  const auto p1 = dir.file("open.obj", open + obj_box("b", {1, 0, 0}, {2, 1, 1}, 8));
  const std::string e1 = input_error([&] { load_pieces(p1); });
  EXPECT_EQ(e1.rfind(p1.string() + ": piece 'a': the piece is not closed: edge (1, 1, 0)-(1, 0, 0) of face 0 "
                     "is used by no other face of the piece", 0), 0u) << e1;
  const auto p2 = dir.file("same.obj", obj_box("a", {0, 0, 0}, {1, 1, 1}, 0) + obj_box("b", {0, 0, 0}, {1, 1, 1}, 8));
  const std::string e2 = input_error([&] { load_pieces(p2); });
  EXPECT_NE(e2.find("coincide but are wound the same way: the pieces overlap"), std::string::npos) << e2;
  const auto p3 = dir.file("plain.obj", obj_box("", {0, 0, 0}, {1, 1, 1}, 0));
  EXPECT_EQ(input_error([&] { load_pieces(p3); }), p3.string() + ": no 'o' or 'g' groups: a pieces file needs one group per piece");
  EXPECT_EQ(input_error([&] { load_pieces(std::vector<std::filesystem::path>{}); }), "pieces: no piece file given");
}

TEST(CoarsePiecesErrors, DegenerateAndFlatPieces) {
  PieceInput flat;
  flat.name = "flat";
  flat.file = "f.obj";
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  flat.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_EQ(input_error([&] { build_pieces_model({flat}); }), "f.obj: piece 'flat': the piece has zero volume");
  PieceInput degenerate = flat;
  degenerate.positions.push_back({1e-13, 0, 0});
  degenerate.triangles = {{0, 3, 2}};
  const std::string e = input_error([&] { build_pieces_model({degenerate}); });
  EXPECT_EQ(e.rfind("f.obj: piece 'flat': face 0 is degenerate: corners coincide", 0), 0u) << e;
  PieceInput empty = flat;
  empty.triangles.clear();
  EXPECT_EQ(input_error([&] { build_pieces_model({empty}); }), "f.obj: piece 'flat': the piece is empty (no faces)");
}

}  // namespace
}  // namespace fracref
