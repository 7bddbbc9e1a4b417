// Cracks inside a piece and virtual fracture (paper 4.1): a non-separating crack is completed
// into a new piece; the crack file's errors.
#include <gtest/gtest.h>

#include <algorithm>

#include "coarse/coarse_model.hpp"
#include "coarse/tet_readers.hpp"
#include "coarse/virtual_fracture.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {
using test::box_vertex;
using test::input_error;
using test::kuhn_box;

// A 2x2x4 box: piece 0 below z = 2, piece 1 above.
TetMesh two_piece_box() { return kuhn_box(2, 2, 4, [](glm::dvec3 c) { return c.z < 2 ? 0 : 1; }); }

// The two triangles of the unit square [x, x+1] x [y, y+1] at height z, as the Kuhn split cuts it
// (diagonal from (x, y) to (x+1, y+1)).
void add_square(CrackList& cracks, int x, int y, int z) {
  const auto v = [&](int i, int j) { return box_vertex(2, 2, i, j, z); };
  cracks.faces.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
  cracks.faces.push_back({v(x, y), v(x, y + 1), v(x + 1, y + 1)});
  cracks.lines.push_back(cracks.lines.size() + 1);
  cracks.lines.push_back(cracks.lines.size() + 1);
}

int count_pieces(const CoarseModel& m, int piece) { return int(std::count(m.tet_piece.begin(), m.tet_piece.end(), piece)); }

TEST(CoarseVirtual, NonSeparatingCrackBecomesAThirdPiece) {
  CrackList cracks;
  cracks.file = "cracks.txt";
  add_square(cracks, 0, 0, 3);  // one quarter of the plane z = 3, inside piece 1
  const CoarseModel m = build_tet_model(two_piece_box(), &cracks);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.virtual_faces_added, 6u);  // the other three quarters of z = 3
  EXPECT_NEAR(m.virtual_area_added, 3.0, 1e-12);
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(count_pieces(m, 0), 48);
  EXPECT_EQ(count_pieces(m, 1), 24);
  EXPECT_EQ(count_pieces(m, 2), 24);
  EXPECT_EQ(m.piece_names[2], "label 1, part 2");
  EXPECT_EQ(m.surface.face_count(), 16u);
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const double z = (m.vertices[m.tets[t].x].z + m.vertices[m.tets[t].y].z + m.vertices[m.tets[t].z].z + m.vertices[m.tets[t].w].z) / 4;
    EXPECT_EQ(m.tet_piece[t], z < 2 ? 0 : (z < 3 ? 1 : 2));
  }
  int upper = 0;
  for (std::size_t f = 0; f < m.surface.face_count(); ++f) {
    if (m.surface.face_pieces[f] != glm::ivec2(2, 1)) continue;
    ++upper;
    EXPECT_EQ(m.surface.positions[m.surface.faces[f].x].z, 3.0f);
  }
  EXPECT_EQ(upper, 8);
}

TEST(CoarseVirtual, CrackFromAFileThroughTheMeditReader) {
  const test::TempDir dir;
  const TetMesh box = two_piece_box();
  std::string text = "MeshVersionFormatted 2\nDimension 3\nVertices\n" + std::to_string(box.vertices.size()) + "\n";
  for (const glm::dvec3& p : box.vertices)
    text += std::to_string(int(p.x)) + " " + std::to_string(int(p.y)) + " " + std::to_string(int(p.z)) + " 0\n";
  text += "Tetrahedra\n" + std::to_string(box.tets.size()) + "\n";
  for (std::size_t t = 0; t < box.tets.size(); ++t)
    text += std::to_string(box.tets[t].x + 1) + " " + std::to_string(box.tets[t].y + 1) + " " + std::to_string(box.tets[t].z + 1) +
            " " + std::to_string(box.tets[t].w + 1) + " " + std::to_string(box.labels[t] * 10 + 3) + "\n";
  text += "End\n";
  const auto mesh = dir.file("box.mesh", text);
  const auto v = [](int i, int j) { return std::to_string(box_vertex(2, 2, i, j, 3)); };
  const auto cracks = dir.file("cracks.txt", "# the corner square at z = 3\n" + v(1, 1) + " " + v(2, 1) + " " + v(2, 2) + "\n" +
                                                 v(1, 1) + " " + v(1, 2) + " " + v(2, 2) + "\n");
  const CoarseModel m = load_tet_model(mesh, cracks);
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.virtual_faces_added, 6u);
  EXPECT_EQ(m.piece_names, (std::vector<std::string>{"label 3", "label 13", "label 13, part 2"}));
  EXPECT_EQ(validate(m.surface), "");
}

TEST(CoarseVirtual, CompleteCrackNeedsNoVirtualFracture) {
  CrackList cracks;
  cracks.file = "cracks.txt";
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y) add_square(cracks, x, y, 3);
  TetModelOptions options;
  options.virtual_fracture = false;
  const CoarseModel m = build_tet_model(two_piece_box(), &cracks, options);
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.virtual_faces_added, 0u);
  EXPECT_EQ(m.virtual_area_added, 0.0);
  EXPECT_EQ(m.surface.face_count(), 16u);
  EXPECT_EQ(validate(m.surface), "");
}

TEST(CoarseVirtual, CrackEndingOnAnotherCutIsCompletedToIt) {
  // A vertical crack x = 1 in the upper piece, only its lower half (z in [2, 3], y in [0, 1]):
  // it must grow up to the top hull and across y, ending on the floor cut z = 2 it starts from.
  CrackList cracks;
  cracks.file = "c";
  const auto v = [](int i, int j, int k) { return box_vertex(2, 2, i, j, k); };
  cracks.faces = {{v(1, 0, 2), v(1, 1, 2), v(1, 1, 3)}, {v(1, 0, 2), v(1, 0, 3), v(1, 1, 3)}};
  cracks.lines = {1, 2};
  const CoarseModel m = build_tet_model(two_piece_box(), &cracks);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.virtual_faces_added, 6u);
  EXPECT_NEAR(m.virtual_area_added, 3.0, 1e-12);
  EXPECT_EQ(test::count_edges(m.surface, kEdgeNonManifold), 2);  // a T-junction with the floor
}

// A platform-independent hash in [-0.5, 0.5) (no <random> distributions: they differ by library).
double jitter(std::uint32_t x) {
  x *= 2654435761u;
  x ^= x >> 13;
  x *= 0x5bd1e995u;
  x ^= x >> 15;
  return double(x % 1000) / 1000.0 - 0.5;
}

TEST(CoarseVirtual, CrackInAnIrregularMeshFollowsItsPlane) {
  // A 6x6x6 box whose inner vertices (except on the cut z = 3) are moved by up to 0.2 per axis.
  const int n = 6;
  TetMesh mesh = kuhn_box(n, n, n, [](glm::dvec3 c) { return c.z < 3 ? 0 : 1; });
  for (std::uint32_t i = 0; i < mesh.vertices.size(); ++i) {
    glm::dvec3& p = mesh.vertices[i];
    if (p.x > 0 && p.x < n && p.y > 0 && p.y < n && p.z > 0 && p.z < n && p.z != 3)
      p += 0.4 * glm::dvec3(jitter(3 * i), jitter(3 * i + 1), jitter(3 * i + 2));
  }
  CrackList cracks{"c", {{box_vertex(n, n, 0, 0, 4), box_vertex(n, n, 1, 0, 4), box_vertex(n, n, 1, 1, 4)}}, {1}};
  const CoarseModel m = build_tet_model(mesh, &cracks);
  EXPECT_EQ(validate(m.surface), "");
  EXPECT_EQ(m.inverted_fixed, 0u);
  EXPECT_EQ(m.piece_count, 3);
  EXPECT_EQ(m.virtual_faces_added, 71u);  // the whole grid layer k = 4: 6 * 6 * 2 - 1 faces
  int upper = 0;
  for (std::size_t f = 0; f < m.surface.face_count(); ++f) {
    if (m.surface.face_pieces[f] != glm::ivec2(2, 1)) continue;
    ++upper;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(m.surface_to_model_vertex[m.surface.faces[f][i]] / ((n + 1) * (n + 1)), 4u);
  }
  EXPECT_EQ(upper, 72);
}

TEST(CoarseVirtual, VirtualFractureOffRejectsANonSeparatingCrack) {
  CrackList cracks;
  cracks.file = "cracks.txt";
  add_square(cracks, 0, 0, 3);
  TetModelOptions options;
  options.virtual_fracture = false;
  const std::string e = input_error([&] { build_tet_model(two_piece_box(), &cracks, options); });
  EXPECT_EQ(e.rfind("cracks.txt:1: the cut through face (0, 0, 3) (1, 0, 3) (1, 1, 3) does not separate piece 'label 1' and "
                    "virtual fracture is off", 0),
            0u)
      << e;
}

TEST(CoarseVirtual, ExtendCracksIsIdleWhenEveryCutSeparates) {
  const std::vector<glm::dvec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  const std::vector<glm::uvec3> interior = {{0, 1, 2}};
  const std::vector<glm::uvec3> hull = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 1, 4}, {1, 2, 4}, {2, 0, 4}};
  std::vector<std::uint8_t> cut = {1};
  const VirtualFractureStats s = extend_cracks(p, interior, hull, cut);
  EXPECT_EQ(s.faces_added, 0u);
  EXPECT_EQ(s.area_added, 0.0);
  std::vector<std::uint8_t> wrong = {};
  EXPECT_THROW(extend_cracks(p, interior, hull, wrong), RunError);
}

TEST(CoarseVirtualErrors, CrackFileErrors) {
  const TetMesh box = two_piece_box();
  const auto fails = [&](std::vector<glm::uvec3> faces) {
    CrackList c{"cracks.txt", std::move(faces), {}};
    for (std::size_t i = 0; i < c.faces.size(); ++i) c.lines.push_back(10 + i);
    return input_error([&] { build_tet_model(box, &c); });
  };
  const auto v = [](int i, int j, int k) { return box_vertex(2, 2, i, j, k); };
  EXPECT_EQ(fails({{0, 1, 999}}), "cracks.txt:10: vertex id 999 is out of range (the mesh has 45 vertices; ids start at 0)");
  EXPECT_EQ(fails({{v(0, 0, 0), v(1, 0, 0), v(1, 1, 0)}}),
            "cracks.txt:10: face 0 1 4 is on the exterior of the mesh, not an interior face");
  EXPECT_EQ(fails({{v(0, 0, 1), v(2, 0, 1), v(2, 2, 1)}}), "cracks.txt:10: face 9 11 17 is not a face of any tetrahedron");
  EXPECT_EQ(fails({{v(0, 0, 2), v(1, 0, 2), v(1, 1, 2)}}),
            "cracks.txt:10: face 18 19 22 lies between pieces already (labels 0 and 1); list only faces inside one piece");
  EXPECT_EQ(fails({{v(0, 0, 3), v(1, 0, 3), v(1, 1, 3)}, {v(1, 1, 3), v(0, 0, 3), v(1, 0, 3)}}),
            "cracks.txt:11: face 31 27 28 repeats the crack of line 10");
  EXPECT_EQ(fails({{5, 5, 6}}), "cracks.txt:10: face 5 5 6 repeats a vertex");
}

TEST(CoarseVirtualErrors, CrackReader) {
  const test::TempDir dir;
  const CrackList ok = read_cracks(dir.file("c.txt", "# cracks\n\n1 2 3  # first\n4 5 6\n"));
  EXPECT_EQ(ok.faces, (std::vector<glm::uvec3>{{1, 2, 3}, {4, 5, 6}}));
  EXPECT_EQ(ok.lines, (std::vector<std::size_t>{3, 4}));
  EXPECT_TRUE(read_cracks(dir.file("empty.txt", "")).faces.empty());
  const auto bad = [&](const std::string& text) {
    const auto p = dir.file("bad.txt", text);
    return input_error([&] { read_cracks(p); }).substr(p.string().size());
  };
  EXPECT_EQ(bad("1 2\n"), ":1: crack face needs 3 values (a b c: 0-based vertex ids), got 2");
  EXPECT_EQ(bad("1 2 3\n1 2 x\n"), ":2: vertex id 'x' is not an integer");
  EXPECT_EQ(bad("1 -2 3\n"), ":1: vertex id -2 is out of range");
  EXPECT_EQ(input_error([&] { read_cracks(dir.path() / "missing.txt"); }),
            (dir.path() / "missing.txt").string() + ": cannot open: no such file");
}

}  // namespace
}  // namespace fracref
