// What the flow is for (issue "The paper's look"): a coarse cut moves into weak material some
// distance away, a staircase in a uniform field flattens in a number of iterations that does not
// grow with its triangles, E never rises, and the run says it converged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "flow/backend.hpp"
#include "refine/refine.hpp"
#include "refine_test_support.hpp"
#include "surface_test_support.hpp"

using namespace fracref;
using namespace fracref::test;

namespace {

const ExteriorSurface& cube() {
  static const ExteriorSurface b = make_exterior(unit_cube(), "cube");
  return b;
}

RefineResult refine(FractureSurface& s, const FieldGrid4& field, double step, double tau, bool tangential = true) {
  auto backend = make_cpu_backend(2);
  RefineOptions o;
  o.tangential_motion = tangential;
  o.scale = cube().diagonal();
  o.tau = tau;
  o.delta = 0.01;
  o.step = step;
  o.tolerance = 1e-4;    // converged: E falls by less than 0.01% in an iteration
  o.rim_motion = true;  // the cube's faces are flat: the rim may slide on them
  return refine_surface(s, field, cube(), *backend, o);
}

void expect_descent_and_convergence(const RefineResult& r) {
  double previous = r.initial_energy;
  for (const IterationStats& st : r.iterations) {
    EXPECT_LE(st.energy, previous * (1.0 + 1e-9)) << "energy rose";
    previous = st.energy;
  }
  EXPECT_EQ(r.stop, RefineResult::Stop::kConverged);
}

// The mean and the largest distance of S's vertices from the plane z = a + b·x + c·y fitted to them
// by least squares.
std::pair<double, double> off_plane(const FractureSurface& s) {
  double m[3][4] = {};
  for (const glm::vec4& p : s.positions) {
    const double row[3] = {1.0, p.x, p.y};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += row[i] * row[j];
      m[i][3] += row[i] * p.z;
    }
  }
  for (int i = 0; i < 3; ++i)  // Gauss-Jordan on the 3x3 normal equations
    for (int k = 0; k < 3; ++k) {
      if (k == i) continue;
      const double f = m[k][i] / m[i][i];
      for (int j = 0; j < 4; ++j) m[k][j] -= f * m[i][j];
    }
  double mean = 0.0, most = 0.0;
  for (const glm::vec4& p : s.positions) {
    const double d = std::abs(p.z - (m[0][3] / m[0][0] + m[1][3] / m[1][1] * p.x + m[2][3] / m[2][2] * p.y));
    mean += d, most = std::max(most, d);
  }
  return {mean / double(s.positions.size()), most};
}

// A narrow valley just below the sheet and a broad one above it: the base level pulls the sheet
// into the narrow one, the pyramid's coarser levels (which ψ's gradient averages in) towards the
// broad one. Once in the narrow valley, the step points uphill for E and does not move S; the
// next iteration's splits are then each on its sample's element, not graded (a flow that could
// not lower E is not expected to pay for splits off the samples).
TEST(RefineFlow, AfterAStepThatDidNotMoveTheSplitsAreOnTheirSamples) {
  const FieldGrid4 field = field_on_cube(33, 5, [](const glm::dvec3& p) {
    const double a = (p.z - 0.47) / 0.03, b = (p.z - 0.75) / 0.12;
    return 1.0 - 0.5 * std::exp(-a * a) - 0.4 * std::exp(-b * b);
  });
  FractureSurface s = sheet(6, 0.5f);
  const RefineResult r = refine(s, field, 0.02, 0.0005);
  ASSERT_EQ(validate(s), "");
  expect_descent_and_convergence(r);
  ASSERT_GE(r.iterations.size(), 3u);
  EXPECT_GT(r.iterations[0].max_displacement, 0.01);
  EXPECT_TRUE(r.iterations[0].graded);
  bool stalled = false;
  for (std::size_t k = 1; k < r.iterations.size(); ++k) {
    const bool moved = r.iterations[k - 1].max_displacement > 0.0;
    stalled |= !moved;
    if (moved) {
      EXPECT_TRUE(r.iterations[k].graded || r.iterations[k].attempts == 2) << "iteration " << k;
    } else {
      EXPECT_FALSE(r.iterations[k].graded) << "iteration " << k;
    }
  }
  EXPECT_TRUE(stalled);
}

}  // namespace

// A planar cut at z = 0.5 in a field whose weak slab lies parallel to it at z = 0.62: the refined
// surface ends inside the slab.
TEST(RefineFlow, PlanarCutMovesIntoAWeakSlab) {
  const FieldGrid4 field = field_on_cube(32, 4, [](const glm::dvec3& p) {
    const double t = (p.z - 0.62) / 0.05;
    return 1.0 - 0.8 * std::exp(-t * t);
  });
  FractureSurface s = sheet(8, 0.5f);
  const RefineResult r = refine(s, field, 0.02, 0.002);
  ASSERT_EQ(validate(s), "");
  expect_descent_and_convergence(r);
  double worst = 0.0, mean = 0.0;
  for (const glm::vec4& p : s.positions) worst = std::max(worst, std::abs(double(p.z) - 0.62)), mean += p.z;
  mean /= double(s.positions.size());
  EXPECT_NEAR(mean, 0.62, 0.02);
  EXPECT_LT(worst, 0.05);  // every vertex inside the slab (its half-width at half depth: 0.042)
}

// A staircase cut (two flat halves 0.1 apart and a ramp between them) in a uniform field flattens
// to a plane, in about as many iterations on a four times finer staircase.
TEST(RefineFlow, StaircaseFlattensInIterationsThatDoNotGrowWithTheTriangles) {
  const FieldGrid4 field = field_on_cube(16, 3, [](const glm::dvec3&) { return 1.0; });
  std::size_t iterations[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const int n = k == 0 ? 8 : 32;
    FractureSurface s = sheet_of(n, [n](int i, int) { return i < n / 2 ? 0.45f : (i > n / 2 ? 0.55f : 0.5f); });
    EXPECT_GT(off_plane(s).second, 0.02);
    const RefineResult r = refine(s, field, 0.02, 1.0);  // τ = 1: the flow alone
    ASSERT_EQ(validate(s), "");
    expect_descent_and_convergence(r);
    const auto [mean, most] = off_plane(s);
    EXPECT_LT(mean, 0.003) << "n = " << n;
    EXPECT_LT(most, 0.01) << "n = " << n;
    iterations[k] = r.iterations.size();
  }
  EXPECT_LE(iterations[1], iterations[0] + iterations[0] / 2 + 2);
}

// A planar cut that grazes a hard cube (ζ 0.9 in a matrix of 0.2, like the Jell-O's fruit),
// 0.03 inside its bottom face, leaves it: the refined surface goes round underneath. (A cut
// through a cube's middle stays: the pull is even both ways, and the flow is local.)
TEST(RefineFlow, ACutGrazingAHardCubeGoesRoundIt) {
  const auto inside = [](const glm::dvec3& p) {
    const double d = std::max({std::abs(p.x - 0.5), std::abs(p.y - 0.5), std::abs(p.z - 0.67)}) - 0.2;
    return std::clamp(0.5 - d / 0.04, 0.0, 1.0);
  };
  const FieldGrid4 field = field_on_cube(32, 4, [&](const glm::dvec3& p) { return 0.25 + 0.7 * inside(p); });
  FractureSurface s = sheet(8, 0.5f);
  const RefineResult r = refine(s, field, 0.02, 0.002);
  ASSERT_EQ(validate(s), "");
  expect_descent_and_convergence(r);
  double in_cube = 0.0, area = 0.0;
  for (const glm::uvec4& f : s.faces) {
    const glm::dvec3 a(s.positions[f.x]), b(s.positions[f.y]), c(s.positions[f.z]);
    const double da = 0.5 * glm::length(glm::cross(b - a, c - a));
    area += da;
    if (inside((a + b + c) / 3.0) > 0.5) in_cube += da;
  }
  EXPECT_GT(area, 1.0);
  EXPECT_LT(in_cube, 0.02 * area) << "of the sheet's area; at the start 16% is in the cube";
}

// A flat cut crossed by a weak valley two cells wide (a wall's brick-mortar interface seen edge
// on): the least-E surface is the flat cut itself, but E's quadrature (ψ at the corners) also
// falls when vertices slide along the sheet into the valley. Free to, they bunch there into
// slivers; held to their normals (tangential_motion off) they stay, and so does the mesh.
TEST(RefineFlow, HeldToTheirNormalsVerticesDoNotBunchInANarrowValley) {
  const FieldGrid4 field = field_on_cube(32, 1, [](const glm::dvec3& p) {
    const double t = (p.x - 0.53) / 0.04;
    return 1.0 - 0.8 * std::exp(-t * t);
  });
  double drift[2] = {0.0, 0.0};
  for (const bool tangential : {true, false}) {
    FractureSurface s = sheet(8, 0.5f);
    const std::vector<glm::vec4> before = s.positions;
    const RefineResult r = refine(s, field, 0.02, 1.0, tangential);  // τ = 1: the flow alone
    ASSERT_EQ(validate(s), "");
    for (const IterationStats& st : r.iterations) EXPECT_LE(st.energy, r.initial_energy * (1.0 + 1e-9));
    for (std::size_t v = 0; v < before.size(); ++v)
      drift[tangential ? 0 : 1] = std::max(drift[tangential ? 0 : 1], double(glm::length(s.positions[v] - before[v])));
  }
  EXPECT_GT(drift[0], 0.01) << "free vertices slide into the valley (what the test guards against)";
  EXPECT_LT(drift[1], 1e-4) << "held to their normals, in a valley across the sheet nothing moves";
}
