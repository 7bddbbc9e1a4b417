// Polygons of mesh files triangulated in their own plane: convex and non-convex, in any plane and
// winding, degenerate ones without a crash, and through the OBJ reader.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "io/mesh_io.hpp"
#include "io/polygon_triangulation.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

using Tris = std::vector<std::array<std::uint32_t, 3>>;

glm::dvec3 area_vector(const std::vector<glm::dvec3>& p, const std::array<std::uint32_t, 3>& t) {
  return 0.5 * glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

glm::dvec3 polygon_area_vector(const std::vector<glm::dvec3>& p) {
  glm::dvec3 a(0.0);
  for (std::size_t i = 0; i < p.size(); ++i) a += 0.5 * glm::cross(p[i], p[(i + 1) % p.size()]);
  return a;
}

// Every triangle wound like the polygon and the areas adding up to the polygon's: the triangles
// tile it without folding over each other or leaving it.
void expect_tiles(const std::vector<glm::dvec3>& p, const Tris& tris) {
  ASSERT_EQ(tris.size(), p.size() - 2);
  const glm::dvec3 whole = polygon_area_vector(p);
  double sum = 0.0;
  for (const auto& t : tris) {
    const glm::dvec3 a = area_vector(p, t);
    EXPECT_GT(glm::dot(a, whole), 0.0) << t[0] << " " << t[1] << " " << t[2];
    sum += glm::length(a);
  }
  EXPECT_NEAR(sum, glm::length(whole), 1e-12 * glm::length(whole));
}

Tris triangulate(const std::vector<glm::dvec3>& p) {
  std::vector<std::uint32_t> v(p.size());
  for (std::uint32_t i = 0; i < v.size(); ++i) v[i] = i;
  Tris out;
  triangulate_polygon(p, v.data(), v.size(), out);
  return out;
}

// An arrow head: its first corner sees the reflex corner from outside, so the fan from it leaves
// the polygon.
const std::vector<glm::dvec3> kArrow = {{0, 0, 0}, {4, 2, 0}, {0, 4, 0}, {1, 2, 0}};

}  // namespace

TEST(PolygonTriangulation, ConvexQuad) { expect_tiles({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, triangulate({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}})); }

TEST(PolygonTriangulation, NonConvexWhereTheFanFails) {
  // The fan (0,1,2), (0,2,3) covers area outside the arrow: its areas do not add up.
  const Tris fan = {{0, 1, 2}, {0, 2, 3}};
  double fan_sum = 0.0;
  for (const auto& t : fan) fan_sum += glm::length(area_vector(kArrow, t));
  EXPECT_GT(fan_sum, glm::length(polygon_area_vector(kArrow)) * 1.01);
  expect_tiles(kArrow, triangulate(kArrow));
}

TEST(PolygonTriangulation, AnyPlaneAndWinding) {
  // A comb with three teeth, in the xz, yz and a tilted plane, both windings.
  std::vector<glm::dvec3> comb = {{0, 0, 0}, {7, 0, 0}, {7, 3, 0}, {6, 3, 0}, {6, 1, 0}, {5, 1, 0}, {5, 3, 0},
                                  {2, 3, 0}, {2, 1, 0}, {1, 1, 0}, {1, 3, 0}, {0, 3, 0}};
  const glm::dmat3 frames[] = {glm::dmat3(1.0), glm::dmat3({1, 0, 0}, {0, 0, 1}, {0, 1, 0}),
                               glm::dmat3({0, 0, 1}, {0, 1, 0}, {1, 0, 0}), glm::dmat3({0.6, 0.8, 0}, {-0.48, 0.36, 0.8}, {0.64, -0.48, 0.6})};
  for (const glm::dmat3& m : frames)
    for (bool reverse : {false, true}) {
      std::vector<glm::dvec3> p;
      for (const glm::dvec3& q : comb) p.push_back(m * q + glm::dvec3(10, -3, 2));
      if (reverse) std::reverse(p.begin(), p.end());
      expect_tiles(p, triangulate(p));
    }
}

TEST(PolygonTriangulation, DegenerateIsFannedWithoutACrash) {
  const std::vector<glm::dvec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_EQ(triangulate(line), (Tris{{0, 1, 2}, {0, 2, 3}}));
  const std::vector<glm::dvec3> same = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  EXPECT_EQ(triangulate(same).size(), 3u);
}

TEST(PolygonTriangulation, ObjReaderTriangulatesNonConvexFacesInTheirPlane) {
  const fs::path file = fs::temp_directory_path() / ("fracref_polygon_" + std::to_string(::getpid()) + ".obj");
  std::ofstream(file) << "v 0 0 0\nv 4 2 0\nv 0 4 0\nv 1 2 0\nf 1 2 3 4\n";
  const MeshSoup soup = read_mesh(file);
  fs::remove(file);
  EXPECT_EQ(soup.polygons, 1u);
  EXPECT_EQ(soup.polygons_triangulated, 1u);
  EXPECT_EQ(soup.triangle_polygon, (std::vector<std::uint32_t>{0, 0}));
  expect_tiles(soup.positions, soup.triangles);
}
