// The `cuts` coarse input: a box exterior with artist cuts becomes a stuffed tet mesh whose
// cracks follow the cuts; a cut across the box separates it, a cut that stops halfway is
// completed by virtual fracture, and a cut outside the box is refused naming the file. Planes
// larger than a torus are clipped to it, a cut through a plate thinner than the first lattice
// cell gets a finer lattice, and an oblique disc inside the cube becomes two pieces.
#include <gtest/gtest.h>

#include <cmath>

#include "coarse/cuts_model.hpp"
#include "surface/fracture_surface.hpp"
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

// The box [lo, hi], wound outward.
MeshSoup box(const glm::dvec3& lo, const glm::dvec3& hi) {
  MeshSoup m = unit_cube();
  for (glm::dvec3& p : m.positions) p = lo + p * (hi - lo);
  return m;
}

// A torus around z (ring radius R, tube radius r), nu x nv quads, wound outward.
MeshSoup torus(double R, double r, int nu, int nv) {
  MeshSoup m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * M_PI * i / nu, v = 2.0 * M_PI * j / nv;
      m.positions.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return std::uint32_t((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

// The square of half-size `half` through c with normal n, as two triangles.
MeshSoup square(const glm::dvec3& c, glm::dvec3 n, double half) {
  n = glm::normalize(n);
  const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  MeshSoup m;
  m.positions = {c - half * u - half * v, c + half * u - half * v, c + half * u + half * v, c - half * u + half * v};
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
              "cuts.obj: cut 2 of 2 (face 3, near (2, 0, -0.2)) lies outside the exterior's bounding box");
  }
  EXPECT_THROW(build_cuts_model(unit_cube(), MeshSoup{}, "empty.obj"), InputError);
}

// Oblique planes three times the torus's size through its ring: each used to leave a slit or a
// wedge at an edge of B that S cannot hold ("side component 0 holds pieces 1 and 2"); now every
// one is clipped to B and gives a valid S.
TEST(CoarseCuts, PlanesLargerThanATorusAreClippedToIt) {
  const MeshSoup ring = torus(1.0, 0.3, 24, 12);
  const glm::dvec3 normals[] = {{0.06, 0.8, -0.6}, {0.79, 0.32, -0.52}, {0.49, -0.81, -0.31}, {-0.28, -0.05, -0.96},
                                {-0.1, 0.3, 0.95}, {-0.65, 0.67, -0.36}, {0.3, 0.2, 0.93}, {0.9, -0.1, 0.42}};
  for (int k = 0; k < 8; ++k) {
    const double a = 0.7 * k;
    const glm::dvec3 c(std::cos(a), std::sin(a), 0.03 * (k - 4));
    SCOPED_TRACE(k);
    CoarseModel m = build_cuts_model(ring, square(c, normals[k], 3.0), "plane.obj");
    EXPECT_GE(m.piece_count, 2);
    EXPECT_EQ(validate(m.surface), "");
    for (const glm::vec4& p : m.surface.positions) {  // S lies inside B: within the tube (B's chords sag 0.011)
      const double rho = std::hypot(double(p.x), double(p.y)) - 1.0;
      EXPECT_LE(std::hypot(rho, double(p.z)), 0.3 + 0.012);
    }
  }
}

// A plate 0.03 thick (a fiftieth of its diagonal): no lattice tet fits at 24 cells per
// diagonal, so the automatic lattice refines; a fixed 24 is refused naming the key.
TEST(CoarseCuts, ACutThroughAThinPlateGetsAFinerLattice) {
  const MeshSoup plate = box({0, 0, 0}, {1, 1, 0.03});
  const MeshSoup cut = square({0.48, 0.5, 0.015}, {1.0, 0.1, 0.0}, 1.0);
  CoarseModel m = build_cuts_model(plate, cut, "cut.obj");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(validate(m.surface), "");
  CutsOptions fixed;
  fixed.cells_per_diagonal = 24.0;
  try {
    build_cuts_model(plate, cut, "cut.obj", fixed);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.obj: no lattice tet lies inside the exterior at 24 cells per diagonal"),
              std::string::npos)
        << e.what();
  }
}

// An oblique disc inside the cube grows in its own plane to the cube's faces: two pieces, not
// the pockets face-by-face growth closed on the lattice (it gave an invalid S here).
TEST(CoarseCuts, AnObliqueDiscInsideTheCubeMakesTwoPieces) {
  MeshSoup disc;
  const glm::dvec3 c(0.52, 0.47, 0.5), n = glm::normalize(glm::dvec3(0.3, 0.5, 0.81));
  const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0))), v = glm::cross(n, u);
  disc.positions.push_back(c);
  for (int s = 0; s < 16; ++s) {
    const double a = 2.0 * M_PI * s / 16;
    disc.positions.push_back(c + 0.25 * (std::cos(a) * u + std::sin(a) * v));
    disc.triangles.push_back({0, std::uint32_t(1 + s), std::uint32_t(1 + (s + 1) % 16)});
  }
  CoarseModel m = build_cuts_model(unit_cube(), disc, "disc.obj");
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_GT(m.virtual_faces_added, 0u);
  EXPECT_EQ(validate(m.surface), "");
  for (const glm::vec4& p : m.surface.positions)  // S stays within about a cell of the disc's plane
    EXPECT_LT(std::abs(glm::dot(glm::dvec3(glm::vec3(p)) - c, n)), 0.1);
}

}  // namespace
}  // namespace fracref
