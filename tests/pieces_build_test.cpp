// build_pieces on hand-made cases: boxes cut by planar and oblique sheets (boundary vertices
// exactly on B's faces, edges and vertices, boundary edges along B edges), a T-junction and a
// cross of pieces, a thin box cut across, and an icosphere cut by a wavy sheet whose boundary
// was projected onto it in float, as the refiner does.
#include <algorithm>
#include <stdexcept>
#include <gtest/gtest.h>

#include "pieces_test_support.hpp"
#include "surface/surface_examples.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_test;

std::size_t count_inside(const PieceSet::Piece& p, std::uint8_t flag) {
  return std::size_t(std::count(p.inside.begin(), p.inside.end(), flag));
}

std::size_t exterior_triangles(const PieceSet& set) {
  std::size_t n = 0;
  for (const auto& p : set.pieces) n += count_inside(p, 0);
  return n;
}

double piece_volume(const PieceSet& set, std::size_t p) { return volume(set.positions, set.pieces[p].triangles); }

// Sheet z = 0 over [0, 3]^2 (4 x 4 vertices) in the 12-triangle box [0, 3]^2 x [-1, 1]: the sheet's
// corners lie inside the box's vertical edges, its sides cross the four side diagonals once.
TEST(PiecesBox, PlanarSheetInTwelveTriangleBox) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  const FractureSurface s = example_sheet(4);
  const PieceSet set = build_pieces(s, b);
  ASSERT_EQ(set.pieces.size(), 2u);
  EXPECT_EQ(std::size_t(set.rim_points_added), 4u);
  EXPECT_EQ(set.snapped_to_b_vertex, 0u);
  // B' = 8 box corners + 12 boundary vertices of S + 4 crossings, closed genus 0: F = 2V - 4.
  EXPECT_EQ(exterior_triangles(set), 2u * (8 + 12 + 4) - 4);
  // Each crossing splits one fracture face into two.
  EXPECT_EQ(count_inside(set.pieces[0], 1), s.faces.size() + 4);
  EXPECT_EQ(count_inside(set.pieces[1], 1), s.faces.size() + 4);
  EXPECT_NEAR(piece_volume(set, 0), 9.0, 1e-12);
  EXPECT_NEAR(piece_volume(set, 1), 9.0, 1e-12);
  expect_valid_pieces(set, b);
}

// The same sheet in a 4 x 4-per-face box: the box has a grid line at z = 0, so the sheet's
// boundary runs along B edges and through B vertices; its corners land on B vertices, and each
// rim edge is split at the B vertices it runs through (x or y = 0.75, 1.5, 2.25), which S's new
// rim vertices take over.
TEST(PiecesBox, PlanarSheetAlongBoxEdges) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 4);
  const FractureSurface s = example_sheet(4);
  const PieceSet set = build_pieces(s, b);
  EXPECT_GE(std::size_t(set.rim_points_added), 12u);
  EXPECT_EQ(set.snapped_to_b_vertex, 4u + 12u);
  // 98 box vertices less those S's rim vertices take over, with S's own and the added ones.
  EXPECT_EQ(set.positions.size(), s.positions.size() + set.rim_points_added + 98 - set.snapped_to_b_vertex);
  // B' = the 98 box vertices + the 8 S vertices inside box edges, closed genus 0: F = 2V - 4.
  EXPECT_EQ(exterior_triangles(set), 2u * (98 + 8) - 4);
  EXPECT_NEAR(piece_volume(set, 0), 9.0, 1e-12);
  expect_valid_pieces(set, b);
}

// An oblique sheet z = 0.3 x + 0.2 y - 0.75 (float positions), boundary exactly on the box's
// side faces; each side holds half the volume.
TEST(PiecesBox, ObliqueSheet) {
  for (int grid : {1, 4}) {
    const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, grid);
    const FractureSurface s = grid_sheet(5, [](int i, int j) {
      const double x = 0.75 * i, y = 0.75 * j;
      return glm::dvec3(x, y, 0.3 * x + 0.2 * y - 0.75);
    });
    const PieceSet set = build_pieces(s, b);
    EXPECT_NEAR(piece_volume(set, 0), 9.0, 1e-5) << "grid " << grid;
    EXPECT_NEAR(piece_volume(set, 1), 9.0, 1e-5) << "grid " << grid;
    expect_valid_pieces(set, b);
  }
}

// Three pieces meeting along a line that reaches the box at two points on opposite faces.
TEST(PiecesJunction, TJunctionInBox) {
  for (int grid : {1, 3}) {
    const MeshSoup b = box({-1, 0, -1}, {1, 2, 1}, grid);
    const FractureSurface s = example_t_junction(2);
    const PieceSet set = build_pieces(s, b);
    ASSERT_EQ(set.pieces.size(), 3u);
    EXPECT_NEAR(piece_volume(set, 0), 4.0, 1e-12) << "grid " << grid;
    EXPECT_NEAR(piece_volume(set, 1), 2.0, 1e-12) << "grid " << grid;
    EXPECT_NEAR(piece_volume(set, 2), 2.0, 1e-12) << "grid " << grid;
    expect_valid_pieces(set, b);
  }
}

TEST(PiecesJunction, CrossOfFourPieces) {
  const MeshSoup b = box({-1, 0, -1}, {1, 3, 1}, 2);
  const PieceSet set = build_pieces(example_cross(3), b);
  ASSERT_EQ(set.pieces.size(), 4u);
  for (std::size_t p = 0; p < 4; ++p) EXPECT_NEAR(piece_volume(set, p), 3.0, 1e-12) << "piece " << p;
  expect_valid_pieces(set, b);
}

// A long thin box cut across, off the box's grid and on a grid plane (boundary along B edges).
TEST(PiecesThin, LongThinBoxCutAcross) {
  for (double x : {5.03, 5.0}) {
    const MeshSoup b = box({0, 0, 0}, {10, 0.1, 0.1}, 8);
    const FractureSurface s = grid_sheet(3, [x](int i, int j) { return glm::dvec3(x, 0.05 * i, 0.05 * j); });
    const PieceSet set = build_pieces(s, b);
    const double xs = double(float(x));
    EXPECT_NEAR(piece_volume(set, 0), xs * 0.01, 1e-9) << "cut at " << x;
    EXPECT_NEAR(piece_volume(set, 1), (10 - xs) * 0.01, 1e-9) << "cut at " << x;
    expect_valid_pieces(set, b);
  }
}

// A polar-grid sheet with a wavy height; the outer ring is projected onto B and rounded to float.
FractureSurface wavy_disk(const MeshSoup& b, int rings, int segments) {
  const Bvh bvh = build_bvh(b.positions, b.triangles);
  auto height = [](double x, double y) { return 0.06 * std::sin(3.0 * x + 0.5) * std::cos(2.0 * y) + 0.1; };
  std::vector<glm::vec4> positions{{0.0f, 0.0f, float(height(0, 0)), 1.0f}};
  for (int r = 1; r <= rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const double angle = 2.0 * 3.14159265358979 * k / segments, radius = double(r) / rings;
      glm::dvec3 p(radius * std::cos(angle), radius * std::sin(angle), 0.0);
      p.z = height(p.x, p.y);
      if (r == rings) p = closest_point(bvh, p).point;
      positions.emplace_back(glm::vec3(p), 1.0f);
    }
  auto id = [segments](int r, int k) { return std::uint32_t(1 + (r - 1) * segments + (k % segments)); };
  std::vector<glm::uvec4> faces;
  for (int k = 0; k < segments; ++k) faces.emplace_back(0, id(1, k), id(1, k + 1), 0);
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      faces.emplace_back(id(r, k), id(r + 1, k), id(r + 1, k + 1), 0);
      faces.emplace_back(id(r, k), id(r + 1, k + 1), id(r, k + 1), 0);
    }
  std::vector<glm::ivec2> pieces(faces.size(), glm::ivec2(1, 0));
  return make_fracture_surface(std::move(positions), std::move(faces), std::move(pieces), 2);
}

TEST(PiecesCurved, IcosphereCutByWavySheet) {
  const MeshSoup b = icosphere(2);
  ASSERT_EQ(b.triangles.size(), 320u);
  for (int segments : {24, 7, 60}) {
    const FractureSurface s = wavy_disk(b, 4, segments);
    const PieceSet set = build_pieces(s, b);
    EXPECT_GT(std::size_t(set.rim_points_added), 0u);
    const PieceReport report = expect_valid_pieces(set, b);
    EXPECT_LT(report.volume_relative_error, 1e-9) << segments << " segments";
  }
}

// Non-convex exteriors. A torus cut by a plane containing its axis (two disks in one surface)
// gives two C-shaped halves; the plane is tilted so that it meets the mesh's grid obliquely.
TEST(PiecesNonConvex, TorusCutInHalves) {
  const MeshSoup b = torus(1.0, 0.4, 32, 12);
  const Bvh bvh = build_bvh(b.positions, b.triangles);
  const glm::dvec3 n(0.05, 1.0, 0.1);
  const FractureSurface s = combine_sheets({disk_sheet(bvh, {1.0, -0.05, 0.0}, n, 0.03, 3, 20, 0.4, 0.8),
                                            disk_sheet(bvh, {-1.0, 0.05, 0.0}, n, 0.03, 3, 20, 1.1, 0.8)},
                                           2);
  const PieceSet set = build_pieces(s, b);
  ASSERT_EQ(set.pieces.size(), 2u);
  const PieceReport report = expect_valid_pieces(set, b);
  EXPECT_GT(report.pieces[0].volume, 0.3 * report.exterior_volume);
  EXPECT_GT(report.pieces[1].volume, 0.3 * report.exterior_volume);
}

// An L-shaped prism (voxels of size 0.5) cut by an oblique plane: the boundary of S crosses the
// concave crease of the L; a second cut across one arm makes three pieces.
TEST(PiecesNonConvex, LShapedPrismCuts) {
  std::set<std::array<int, 3>> cells;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        if (x < 2 || y < 2) cells.insert({x, y, z});
  const MeshSoup b = voxel_surface(cells, 0.5);
  // Sheet over the L on a 0.25 lattice: z = 0.5 + 0.1 x - 0.07 y.
  SheetArrays sheet;
  std::map<std::pair<int, int>, std::uint32_t> ids;
  auto vertex = [&](int i, int j) {
    auto [it, inserted] = ids.try_emplace({i, j}, std::uint32_t(sheet.positions.size()));
    const double x = 0.25 * i, y = 0.25 * j;
    if (inserted) sheet.positions.emplace_back(float(x), float(y), float(0.5 + 0.1 * x - 0.07 * y), 1.0f);
    return it->second;
  };
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      if (i >= 4 && j >= 4) continue;
      const std::uint32_t a = vertex(i, j), c = vertex(i + 1, j + 1);
      sheet.faces.emplace_back(a, vertex(i + 1, j), c, 0);
      sheet.faces.emplace_back(a, c, vertex(i, j + 1), 0);
    }
  sheet.pieces.assign(sheet.faces.size(), glm::ivec2(1, 0));
  const PieceSet two = build_pieces(combine_sheets({sheet}, 2), b);
  expect_valid_pieces(two, b);
  // Both arms cut off across (planes y = 1.6 and x = 1.6): three pieces, exact volumes.
  SheetArrays top, right;
  for (int k = 0; k <= 4; ++k)
    for (int i = 0; i <= 4; ++i) {
      top.positions.emplace_back(0.25f * float(i), 1.6f, 0.25f * float(k), 1.0f);
      right.positions.emplace_back(1.6f, 0.25f * float(i), 0.25f * float(k), 1.0f);
    }
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 4; ++i) {
      const std::uint32_t a = std::uint32_t(k * 5 + i);
      top.faces.emplace_back(a, a + 6, a + 1, 0);  // normal +y, into the top arm's tip
      top.faces.emplace_back(a, a + 5, a + 6, 0);
      right.faces.emplace_back(a, a + 1, a + 6, 0);  // normal +x, into the right arm's tip
      right.faces.emplace_back(a, a + 6, a + 5, 0);
    }
  top.pieces.assign(top.faces.size(), glm::ivec2(1, 0));
  right.pieces.assign(right.faces.size(), glm::ivec2(2, 0));
  const PieceSet three = build_pieces(combine_sheets({top, right}, 3), b);
  expect_valid_pieces(three, b);
  EXPECT_NEAR(piece_volume(three, 1), 1.0 * (2.0 - double(1.6f)), 1e-12);
  EXPECT_NEAR(piece_volume(three, 2), 1.0 * (2.0 - double(1.6f)), 1e-12);
  EXPECT_NEAR(piece_volume(three, 0), 3.0 - 2.0 * (2.0 - double(1.6f)), 1e-12);
}

TEST(PiecesDeterminism, SameInputSameOutput) {
  const MeshSoup b = icosphere(2);
  const FractureSurface s = wavy_disk(b, 3, 20);
  const PieceSet first = build_pieces(s, b), second = build_pieces(s, b);
  EXPECT_EQ(first.positions, second.positions);
  ASSERT_EQ(first.pieces.size(), second.pieces.size());
  for (std::size_t p = 0; p < first.pieces.size(); ++p) EXPECT_EQ(first.pieces[p].triangles, second.pieces[p].triangles);
}

// Refined surfaces come with boundary vertices a hair apart and faces lying flat on B: the rim
// embedded in B takes both as they are, in one pass (nothing is contracted or left out).
// The face of `faces` on boundary edge p1-p2 (either direction) split by a new vertex a hair
// before p2: (v1, w, r) and the sliver (w, v2, r). False when there is no such face.
bool insert_hair_vertex(std::vector<glm::vec4>& positions, std::vector<glm::uvec4>& faces, std::vector<glm::ivec2>& pieces,
                        glm::vec3 p1, glm::vec3 p2) {
  const auto at = [&](glm::vec3 p) {
    return std::uint32_t(std::find(positions.begin(), positions.end(), glm::vec4(p, 1.0f)) - positions.begin());
  };
  const std::uint32_t v1 = at(p1), v2 = at(p2), w = std::uint32_t(positions.size());
  positions.emplace_back(p2 + 1e-6f * (p1 - p2), 1.0f);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = faces[f][k], c = faces[f][(k + 1) % 3], r = faces[f][(k + 2) % 3];
      if (!((a == v1 && c == v2) || (a == v2 && c == v1))) continue;
      faces[f] = glm::uvec4(a, w, r, 0);
      faces.emplace_back(w, c, r, 0);
      pieces.push_back(pieces[f]);
      return true;
    }
  return false;
}

// The 4 x 4 example sheet with a hair vertex on each given boundary edge; false when an edge
// is not one.
bool sheet_with_hairs(std::initializer_list<std::pair<glm::vec3, glm::vec3>> edges, FractureSurface& out) {
  const FractureSurface sheet = example_sheet(4);
  std::vector<glm::vec4> positions = sheet.positions;
  std::vector<glm::uvec4> faces = sheet.faces;
  std::vector<glm::ivec2> pieces = sheet.face_pieces;
  for (const auto& [p1, p2] : edges)
    if (!insert_hair_vertex(positions, faces, pieces, p1, p2)) return false;
  out = make_fracture_surface(positions, faces, pieces, 2);
  return true;
}

TEST(PiecesRim, HairShortRimEdgeIsKept) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  FractureSurface s;
  // On the boundary edge y = 0 from (1,0,0) to (2,0,0).
  ASSERT_TRUE(sheet_with_hairs({{{1, 0, 0}, {2, 0, 0}}}, s));
  const PieceSet set = build_pieces(s, b);
  EXPECT_NEAR(piece_volume(set, 0), 9.0, 1e-12);
  expect_valid_pieces(set, b);
}

TEST(PiecesRim, HairEdgesFarApartAreKept) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  FractureSurface s;
  ASSERT_TRUE(sheet_with_hairs({{{1, 0, 0}, {2, 0, 0}}, {{1, 3, 0}, {2, 3, 0}}}, s));
  const PieceSet set = build_pieces(s, b);
  EXPECT_NEAR(piece_volume(set, 0), 9.0, 1e-12);
  expect_valid_pieces(set, b);
}

// The 4x4 example sheet in the 3x3x2 box with flaps folded up onto the box's sides: each flap
// is a triangle from a boundary edge (from, to), in the direction that continues the sheet's
// winding, to a tip above the edge's midpoint.
namespace {
FractureSurface sheet_with_flaps(const std::vector<std::pair<glm::vec4, glm::vec4>>& edges) {
  const FractureSurface sheet = example_sheet(4);
  std::vector<glm::vec4> positions = sheet.positions;
  std::vector<glm::uvec4> faces = sheet.faces;
  std::vector<glm::ivec2> pieces = sheet.face_pieces;
  auto vertex_at = [&](glm::vec4 p) {
    return std::uint32_t(std::find(positions.begin(), positions.end(), p) - positions.begin());
  };
  for (const auto& [from, to] : edges) {
    const std::uint32_t a = vertex_at(from), b = vertex_at(to);
    if (std::max(a, b) >= sheet.positions.size()) throw std::logic_error("no such sheet vertex");
    positions.push_back(0.5f * (from + to) + glm::vec4(0.0f, 0.0f, 0.5f, 0.0f));
    faces.emplace_back(a, b, std::uint32_t(positions.size() - 1), 0);
    pieces.emplace_back(1, 0);
  }
  return make_fracture_surface(positions, faces, pieces, 2);
}
}  // namespace

// A flap folded up onto the box face y = 0 from the boundary edge (1,0,0)-(2,0,0): it lies on B,
// outside nothing, and the pieces stay valid.
TEST(PiecesRim, FlapLyingOnExteriorKeepsThePiecesValid) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  const FractureSurface s = sheet_with_flaps({{{2, 0, 0, 1}, {1, 0, 0, 1}}});
  ASSERT_EQ(validate(s), "");
  const PieceSet set = build_pieces(s, b);
  EXPECT_NEAR(piece_volume(set, 0) + piece_volume(set, 1), 18.0, 1e-9);
  expect_valid_pieces(set, b);
}

TEST(PiecesErrors, InvalidSurfaceIsRunError) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  FractureSurface s = example_sheet(4);
  s.face_pieces[3] = glm::ivec2(0, 1);  // flipped pieces, winding kept: the sides disagree
  try {
    build_pieces(s, b);
    FAIL() << "expected a RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("the fracture surface is not valid: "), std::string::npos) << e.what();
  }
}

TEST(PiecesErrors, BoundaryVertexFarFromExterior) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  FractureSurface s = example_sheet(4);
  s.positions[1].y = -0.5f;  // vertex (1, 0, 0), a boundary vertex, pulled out of the box
  try {
    build_pieces(s, b);
    FAIL() << "expected a RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("boundary vertex 1 "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("from the exterior"), std::string::npos) << e.what();
  }
}

TEST(PiecesErrors, OpenOrInwardExteriorIsInputError) {
  MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  MeshSoup open = b;
  open.triangles.pop_back();
  EXPECT_THROW(build_pieces(example_sheet(4), open), InputError);
  MeshSoup inward = b;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  try {
    build_pieces(example_sheet(4), inward);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wound inward"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fracref
