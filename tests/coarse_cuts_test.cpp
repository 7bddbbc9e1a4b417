// The `cuts` coarse input: a box exterior with artist cuts becomes a stuffed tet mesh whose
// cracks follow the cuts; a cut across the box separates it, a cut that stops halfway is
// completed by virtual fracture, and a cut outside the box is refused naming the file.
#include <gtest/gtest.h>

#include <cmath>

#include "coarse/cuts_model.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// The unit cube, wound outward.
MeshSoup unit_cube() {
  MeshSoup m;
  for (int i = 0; i < 8; ++i) m.positions.push_back(glm::dvec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

// The square x = x0, y in [y0, y1], z in [-0.2, 1.2], as two triangles.
MeshSoup cut_x(double x0, double y0, double y1) {
  MeshSoup m;
  m.positions = {{x0, y0, -0.2}, {x0, y1, -0.2}, {x0, y1, 1.2}, {x0, y0, 1.2}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

double area(const FractureSurface& s) {
  double a = 0.0;
  for (const glm::uvec4& f : s.faces) {
    const glm::dvec3 p(glm::vec3(s.positions[f.x])), q(glm::vec3(s.positions[f.y])), r(glm::vec3(s.positions[f.z]));
    a += 0.5 * glm::length(glm::cross(q - p, r - p));
  }
  return a;
}

// Every vertex of S, its mean x.
double mean_x(const FractureSurface& s) {
  double x = 0.0;
  for (const glm::vec4& p : s.positions) x += p.x;
  return x / double(s.positions.size());
}

TEST(CoarseCuts, APlanarCutAcrossTheBoxMakesTwoPieces) {
  CoarseModel m = build_cuts_model(unit_cube(), cut_x(0.53, -0.2, 1.2), "cut.obj");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(m.virtual_faces_added, 0u);
  EXPECT_EQ(m.virtual_area_added, 0.0);
  ASSERT_GT(m.surface.faces.size(), 0u);
  // S lies within one lattice cell (diag / 24) of the cut and spans the box's section.
  const double h = std::sqrt(3.0) / 24.0;
  for (const glm::vec4& p : m.surface.positions) EXPECT_NEAR(p.x, 0.53, h);
  EXPECT_NEAR(mean_x(m.surface), 0.53, 0.5 * h);
  EXPECT_GT(area(m.surface), 0.99);
  std::printf("spanning cut: %zu coarse triangles, %zu tets\n", m.surface.faces.size(), m.tets.size());
}

TEST(CoarseCuts, ACutStoppingHalfwayIsCompletedByVirtualFracture) {
  CoarseModel m = build_cuts_model(unit_cube(), cut_x(0.53, -0.2, 0.5), "half.obj");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_GT(m.virtual_faces_added, 0u);
  EXPECT_GT(m.virtual_area_added, 0.0);
  EXPECT_GT(area(m.surface), 0.99);
  std::printf("halfway cut: %zu coarse triangles, %zu faces (area %.3f) added by virtual fracture\n",
              m.surface.faces.size(), m.virtual_faces_added, m.virtual_area_added);
  CutsOptions off;
  off.virtual_fracture = false;
  EXPECT_THROW(build_cuts_model(unit_cube(), cut_x(0.53, -0.2, 0.5), "half.obj", off), InputError);
}

TEST(CoarseCuts, TwoCutsMakeThreePieces) {
  MeshSoup cuts = cut_x(0.31, -0.2, 1.2), b = cut_x(0.72, -0.2, 1.2);
  for (const auto& t : b.triangles) cuts.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});
  cuts.positions.insert(cuts.positions.end(), b.positions.begin(), b.positions.end());
  CoarseModel m = build_cuts_model(unit_cube(), cuts, "two.obj");
  EXPECT_EQ(m.piece_count, 3);
}

TEST(CoarseCuts, ACutOutsideTheExteriorIsAnError) {
  MeshSoup cuts = cut_x(0.53, -0.2, 1.2), out = cut_x(2.0, 0.0, 1.0);
  for (const auto& t : out.triangles) cuts.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});
  cuts.positions.insert(cuts.positions.end(), out.positions.begin(), out.positions.end());
  try {
    build_cuts_model(unit_cube(), cuts, "cuts.obj");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cuts.obj: cut 2 of 2 (face 3, near (2, 0, -0.2)) crosses no tet face inside the exterior at 96 cells "
              "per diagonal: it lies outside the exterior or is smaller than the lattice cell");
  }
  EXPECT_THROW(build_cuts_model(unit_cube(), MeshSoup{}, "empty.obj"), InputError);
}

}  // namespace
}  // namespace fracref
