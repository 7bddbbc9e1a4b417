// Pieces that nearly conform (issue 30): gaps, overlaps, cuts triangulated differently,
// degenerate faces, fitted on a tet lattice of the exterior; conforming pieces keep the exact path;
// the errors for gaps wider than the tolerance and pieces outside the exterior.
#include <gtest/gtest.h>

#include <cmath>

#include "coarse/pieces_fit.hpp"
#include "coarse_test_support.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {
using test::input_error;

// An axis-aligned box, 8 corners and 12 outward triangles.
void add_box(std::vector<glm::dvec3>& x, std::vector<std::array<std::uint32_t, 3>>& t, glm::dvec3 lo, glm::dvec3 hi) {
  const auto base = std::uint32_t(x.size());
  for (int k = 0; k < 8; ++k) x.emplace_back(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    t.push_back({base + q[0], base + q[1], base + q[2]});
    t.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

PieceInput box_piece(const std::string& name, glm::dvec3 lo, glm::dvec3 hi) {
  PieceInput p;
  p.name = name;
  p.file = "pieces.obj";
  add_box(p.positions, p.triangles, lo, hi);
  return p;
}

MeshSoup box_exterior(glm::dvec3 lo, glm::dvec3 hi) {
  MeshSoup s;
  add_box(s.positions, s.triangles, lo, hi);
  return s;
}

FitOptions coarse_fit() {
  FitOptions o;
  o.cells_per_diagonal = 12;  // quick
  return o;
}

// Every tet-model invariant of S holds, and both pieces are there by name.
void expect_two_pieces(const CoarseModel& m) {
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"left", "right"}));
  EXPECT_GT(m.surface.face_count(), 0u);
}

TEST(CoarseFit, ConformingPiecesKeepTheExactPath) {
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), box_piece("right", {1, 0, 0}, {2, 1, 1})};
  const CoarseModel exact = build_pieces_model(pieces);
  const CoarseModel m = build_pieces_or_fit(box_exterior({0, 0, 0}, {2, 1, 1}), "b.obj", pieces, {}, coarse_fit());
  EXPECT_FALSE(m.fit.fitted);
  EXPECT_EQ(m.surface.faces, exact.surface.faces);
  EXPECT_EQ(m.surface.positions, exact.surface.positions);
  EXPECT_EQ(m.vertices, exact.vertices);
}

TEST(CoarseFit, TwoCubesAGapApartAreFitted) {
  // The crash report of issue 30: two cubes 0.01 apart gave no S (coarse_triangles: 0).
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), box_piece("right", {1.01, 0, 0}, {2.01, 1, 1})};
  const CoarseModel m = build_pieces_or_fit(box_exterior({0, 0, 0}, {2.01, 1, 1}), "b.obj", pieces, {}, coarse_fit());
  expect_two_pieces(m);
  EXPECT_TRUE(m.fit.fitted);
  EXPECT_EQ(m.fit.reason, "no face of one piece matches a face of another");
  EXPECT_NEAR(m.fit.pieces_volume, 2.0, 1e-12);
  EXPECT_NEAR(m.fit.exterior_volume, 2.01, 1e-12);
  EXPECT_FALSE(m.tets.empty());
  for (const glm::vec4& p : m.surface.positions)  // S runs through the gap, within a cell
    if (p.y > 0.01f && p.y < 0.99f && p.z > 0.01f && p.z < 0.99f) {
      EXPECT_NEAR(p.x, 1.005, 0.25);
    }
}

TEST(CoarseFit, CutTriangulatedDifferentlyOnTwoSidesIsFitted) {
  // The right cube's face x = 1 is split along the other diagonal: no face matches.
  PieceInput right = box_piece("right", {1, 0, 0}, {2, 1, 1});
  for (auto& t : right.triangles) {  // quad {0, 4, 6, 2} (x = lo) as (0 4 2) (4 6 2)
    if (t == std::array<std::uint32_t, 3>{0, 4, 6}) t = {0, 4, 2};
    else if (t == std::array<std::uint32_t, 3>{0, 6, 2}) t = {4, 6, 2};
  }
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), right};
  EXPECT_THROW(build_pieces_model(pieces), PiecesMismatch);
  const CoarseModel m = build_pieces_or_fit(box_exterior({0, 0, 0}, {2, 1, 1}), "b.obj", pieces, {}, coarse_fit());
  expect_two_pieces(m);
  EXPECT_NE(m.fit.reason.find("do not conform"), std::string::npos) << m.fit.reason;
}

TEST(CoarseFit, OverlapAndDegenerateFacesAreFitted) {
  PieceInput left = box_piece("left", {0, 0, 0}, {1.2, 1, 1});  // overlaps right by 0.2
  left.positions.push_back(left.positions[0]);
  left.triangles.push_back({0, 8, 1});  // a degenerate face
  const std::vector<PieceInput> pieces{left, box_piece("right", {1, 0, 0}, {2, 1, 1})};
  const CoarseModel m = build_pieces_or_fit(box_exterior({0, 0, 0}, {2, 1, 1}), "b.obj", pieces, {}, coarse_fit());
  expect_two_pieces(m);
  EXPECT_NE(m.fit.reason.find("degenerate"), std::string::npos) << m.fit.reason;
  EXPECT_GT(m.fit.overlap_volume, 0.0);
}

TEST(CoarseFit, SameBytesOnAnyThreadCount) {
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), box_piece("right", {1.01, 0, 0}, {2.01, 1, 1})};
  const MeshSoup b = box_exterior({0, 0, 0}, {2.01, 1, 1});
  set_default_threads(1);
  const CoarseModel one = build_pieces_or_fit(b, "b.obj", pieces);
  set_default_threads(3);
  const CoarseModel three = build_pieces_or_fit(b, "b.obj", pieces);
  set_default_threads(0);
  EXPECT_EQ(one.surface.faces, three.surface.faces);
  EXPECT_EQ(one.surface.positions, three.surface.positions);
  EXPECT_EQ(one.tet_piece, three.tet_piece);
}

TEST(CoarseFitErrors, GapWiderThanTheToleranceNamesTheKey) {
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), box_piece("right", {1.5, 0, 0}, {2.5, 1, 1})};
  const std::string e =
      input_error([&] { build_pieces_or_fit(box_exterior({0, 0, 0}, {2.5, 1, 1}), "b.obj", pieces, {}, coarse_fit()); });
  EXPECT_EQ(e.rfind("pieces.obj: the pieces do not fill the exterior: the point (", 0), 0u) << e;
  EXPECT_NE(e.find("farther than fracture.tolerance (0.005 of the diagonal"), std::string::npos) << e;
}

TEST(CoarseFitErrors, PieceOutsideTheExteriorIsNamed) {
  const std::vector<PieceInput> pieces{box_piece("left", {0, 0, 0}, {1, 1, 1}), box_piece("right", {1.001, 0, 0}, {2, 1, 1}),
                                       box_piece("far", {5, 5, 5}, {6, 6, 6})};
  const std::string e =
      input_error([&] { build_pieces_or_fit(box_exterior({0, 0, 0}, {2, 1, 1}), "b.obj", pieces, {}, coarse_fit()); });
  EXPECT_EQ(e.rfind("pieces.obj: piece 'far' holds no tet of the exterior's lattice", 0), 0u) << e;
}

TEST(CoarseFitErrors, MalformedPiecesStayErrors) {
  PieceInput nan = box_piece("left", {0, 0, 0}, {1, 1, 1});
  nan.positions[3].x = std::nan("");
  const std::string e = input_error([&] { build_pieces_or_fit(box_exterior({0, 0, 0}, {1, 1, 1}), "b.obj", {nan}); });
  EXPECT_EQ(e, "pieces.obj: piece 'left': a position is not finite");
  EXPECT_EQ(input_error([&] { build_pieces_or_fit(box_exterior({0, 0, 0}, {1, 1, 1}), "b.obj", {}); }), "pieces: no piece given");
}

}  // namespace
}  // namespace fracref
