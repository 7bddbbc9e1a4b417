// check_pieces catches every kind of broken piece set; write_pieces writes files that read back;
// the cut B triangle's constrained triangulation on small cases with known counts.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <unistd.h>

#include "animate/piece_surface.hpp"
#include "io/mesh_io.hpp"
#include "pieces/pieces_internal.hpp"
#include "pieces_test_support.hpp"
#include "surface/surface_examples.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_test;
using namespace pieces_detail;

struct Fixture {
  MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  PieceSet set = build_pieces(example_sheet(4), b);
};

std::string joined(const PieceReport& r) {
  std::string s;
  for (const auto& f : r.failures) s += f + "\n";
  return s;
}

bool mentions(const PieceReport& r, const std::string& text) { return joined(r).find(text) != std::string::npos; }

TEST(PiecesCheck, ValidSetPasses) {
  Fixture f;
  const PieceReport r = check_pieces(f.set, f.b);
  EXPECT_TRUE(r.ok()) << joined(r);
  EXPECT_NEAR(r.exterior_volume, 18.0, 1e-12);
  EXPECT_NEAR(r.volume_sum, 18.0, 1e-12);
  EXPECT_EQ(r.points_tested, 2000u);
  EXPECT_NO_THROW(require_valid_pieces(r));
}

TEST(PiecesCheck, MissingTriangleIsOpenAndLeaksPoints) {
  Fixture f;
  f.set.pieces[1].triangles.pop_back();
  f.set.pieces[1].inside.pop_back();
  const PieceReport r = check_pieces(f.set, f.b);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.pieces[1].open_edges, 3u);
  EXPECT_TRUE(mentions(r, "piece 1: not closed (3 edges with one face")) << joined(r);
  EXPECT_TRUE(r.pieces[0].closed());
  try {
    require_valid_pieces(r);
    FAIL();
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("piece 1: not closed"), std::string::npos);
  }
}

TEST(PiecesCheck, InvertedPieceIsNotOutwardAndBreaksPartition) {
  Fixture f;
  for (auto& t : f.set.pieces[0].triangles) std::swap(t[1], t[2]);
  const PieceReport r = check_pieces(f.set, f.b);
  EXPECT_TRUE(mentions(r, "piece 0: not outward (volume -9")) << joined(r);
  EXPECT_TRUE(mentions(r, "pieces: volumes sum to 0")) << joined(r);
}

TEST(PiecesCheck, FlippedTriangleIsInconsistentlyOriented) {
  Fixture f;
  std::swap(f.set.pieces[0].triangles[0][1], f.set.pieces[0].triangles[0][2]);
  const PieceReport r = check_pieces(f.set, f.b);
  EXPECT_EQ(r.pieces[0].misoriented_edges, 3u);
  EXPECT_TRUE(mentions(r, "piece 0: inconsistently oriented (3 edges")) << joined(r);
}

TEST(PiecesCheck, DuplicatedPieceOverlaps) {
  Fixture f;
  f.set.pieces.push_back(f.set.pieces[0]);
  const PieceReport r = check_pieces(f.set, f.b);
  EXPECT_GT(r.points_in_several_pieces, 0u);
  EXPECT_TRUE(mentions(r, "points inside the exterior lie in several pieces")) << joined(r);
}

TEST(PiecesCheck, EmptyPieceAndMovedVertex) {
  Fixture f;
  f.set.pieces.emplace_back();
  const PieceReport empty = check_pieces(f.set, f.b);
  EXPECT_TRUE(mentions(empty, "piece 2: empty")) << joined(empty);
  Fixture g;
  // Push a fracture vertex far through the exterior: piece faces now cross each other.
  const auto centre = std::find(g.set.positions.begin(), g.set.positions.end(), glm::dvec3(1, 1, 0));
  ASSERT_NE(centre, g.set.positions.end());
  centre->z = 5.0;
  const PieceReport moved = check_pieces(g.set, g.b);
  EXPECT_GT(moved.pieces[0].self_intersections + moved.pieces[1].self_intersections, 0u);
  EXPECT_TRUE(mentions(moved, "pairs of intersecting faces")) << joined(moved);
}

TEST(PiecesCheck, IndexOutOfRangeIsRunError) {
  Fixture f;
  f.set.pieces[0].triangles[0][0] = 1000;
  EXPECT_THROW(check_pieces(f.set, f.b), RunError);
}

std::filesystem::path temp_folder(const std::string& name) {
  // Unique per process (ctest runs tests in parallel processes).
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("fracref_pieces_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(p);
  return p;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(PiecesWrite, PlyAndObjReadBack) {
  Fixture f;
  const std::filesystem::path dir = temp_folder("write");
  write_pieces(f.set, dir);
  write_piece_objs(f.set, dir);
  for (std::size_t p = 0; p < 2; ++p) {
    const std::string stem = "piece_00" + std::to_string(p);
    const MeshSoup ply = read_mesh(dir / "pieces" / (stem + ".ply"));
    const auto& piece = f.set.pieces[p];
    ASSERT_EQ(ply.triangles.size(), piece.triangles.size());
    ASSERT_EQ(ply.face_properties.size(), 1u);
    EXPECT_EQ(ply.face_properties[0].name, "inside");
    EXPECT_EQ(ply.face_properties[0].type, PropertyType::UInt8);
    for (std::size_t t = 0; t < piece.triangles.size(); ++t) {
      EXPECT_EQ(ply.face_properties[0].values[t], double(piece.inside[t]));
      for (int k = 0; k < 3; ++k) EXPECT_EQ(ply.positions[ply.triangles[t][k]], f.set.positions[piece.triangles[t][k]]);
    }
    ASSERT_EQ(ply.vertex_properties.size(), 3u);
    EXPECT_EQ(ply.vertex_properties[0].name, "mx");
    EXPECT_EQ(ply.vertex_properties[2].name, "mz");
    for (std::size_t v = 0; v < ply.positions.size(); ++v) EXPECT_EQ(ply.vertex_properties[1].values[v], ply.positions[v].y);
    const MeshSoup obj = read_mesh(dir / "pieces" / (stem + ".obj"));
    EXPECT_EQ(obj.triangles.size(), piece.triangles.size());
    EXPECT_EQ(obj.positions, ply.positions);
    const std::string text = read_text(dir / "pieces" / (stem + ".obj"));
    EXPECT_NE(text.find("mtllib pieces.mtl"), std::string::npos);
    EXPECT_LT(text.find("usemtl outside"), text.find("usemtl inside"));
    // The inside group holds exactly the fracture faces.
    const std::size_t inside_faces = std::size_t(std::count(piece.inside.begin(), piece.inside.end(), 1));
    const std::string tail = text.substr(text.find("usemtl inside"));
    EXPECT_EQ(std::size_t(std::count(tail.begin(), tail.end(), 'f')), inside_faces);
  }
  const std::string mtl = read_text(dir / "pieces" / "pieces.mtl");
  EXPECT_NE(mtl.find("newmtl inside"), std::string::npos);
  EXPECT_NE(mtl.find("newmtl outside"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A cut triangle with two points on side 0, one on side 1, one inside, and a constraint path
// from side 0 through the inside point to side 1: 2 i + b - 2 triangles, constraints as edges.
TEST(PiecesTriangulate, CutTriangleKeepsConstraints) {
  CutTriangle in;
  in.uv = {{0, 0}, {1, 0}, {0, 1}, {0.25, 0}, {0.6, 0}, {0.5, 0.5}, {0.3, 0.2}};
  for (const auto& p : in.uv) in.xyz.emplace_back(p.x, p.y, 0.0);
  in.side_points[0] = {3, 4};
  in.side_points[1] = {5};
  in.interior = {6};
  in.constraints = {{3, 6}, {6, 5}};
  const auto tris = triangulate_cut_triangle(in);
  EXPECT_EQ(tris.size(), 2u * 1 + 6 - 2);
  double area = 0.0;
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& t : tris) {
    const glm::dvec2 a = in.uv[t[0]], b = in.uv[t[1]], c = in.uv[t[2]];
    const double twice = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    EXPECT_GT(twice, 0.0);
    area += twice / 2;
    for (int k = 0; k < 3; ++k) edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  }
  EXPECT_DOUBLE_EQ(area, 0.5);
  EXPECT_TRUE(edges.count({3, 6}));
  EXPECT_TRUE(edges.count({5, 6}));
}

// An edge to avoid (a chord of S between two of the points) is flipped away where its quad is
// convex; the triangulation still covers the triangle counterclockwise.
TEST(PiecesTriangulate, EdgeToAvoidIsFlippedAway) {
  CutTriangle in;
  in.uv = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}, {0.3, 0.3}};
  for (const auto& p : in.uv) in.xyz.emplace_back(p.x, p.y, 0.0);
  in.side_points = {std::vector<std::uint32_t>{3}, std::vector<std::uint32_t>{4}, std::vector<std::uint32_t>{5}};
  in.interior = {6};
  auto interior_edges = [&](const std::vector<std::array<std::uint32_t, 3>>& tris) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : tris)
      for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    for (const auto& [e, n] : uses)
      if (n == 2) out.push_back(e);
    return out;
  };
  const auto before = triangulate_cut_triangle(in);
  std::size_t flipped = 0;
  for (const auto& e : interior_edges(before)) {
    CutTriangle avoid = in;
    avoid.avoid = {e};
    const auto after = triangulate_cut_triangle(avoid);
    ASSERT_EQ(after.size(), before.size());
    double area = 0.0;
    for (const auto& t : after) {
      const glm::dvec2 a = in.uv[t[0]], b = in.uv[t[1]], c = in.uv[t[2]];
      const double twice = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      EXPECT_GT(twice, 0.0);
      area += twice / 2;
    }
    EXPECT_DOUBLE_EQ(area, 0.5);
    const auto edges = interior_edges(after);
    flipped += std::find(edges.begin(), edges.end(), e) == edges.end();
  }
  EXPECT_GT(flipped, 0u);  // at least the edges in convex quads go
}

TEST(PiecesTriangulate, CrossingConstraintsAreRejected) {
  CutTriangle in;
  in.uv = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}, {0.2, 0.0}, {0.0, 0.2}};
  for (const auto& p : in.uv) in.xyz.emplace_back(p.x, p.y, 0.0);
  in.side_points[0] = {6, 3};
  in.side_points[1] = {4};
  in.side_points[2] = {5, 7};
  in.constraints = {{3, 5}, {6, 4}};
  EXPECT_THROW(triangulate_cut_triangle(in), RunError);
}

}  // namespace
}  // namespace fracref
