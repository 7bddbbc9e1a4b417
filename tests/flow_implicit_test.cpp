// The semi-implicit flow step (flow/implicit_step.hpp): small steps are the explicit ones, the
// fixed points are the velocity's, the filter holds, and the result is a descent direction whose
// length does not shrink with the triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "flow/implicit_step.hpp"
#include "flow/velocity.hpp"
#include "flow_test_support.hpp"

using namespace fracref;
using fracref::test::linear_field;

namespace {

/// An n×n grid sheet over [-1, 1]² at height h(x, y), with its vertex→faces CSR.
struct Sheet : fracref::test::FlatMesh {
  std::vector<glm::vec4> samples, velocity;
};

template <class Height>
Sheet sheet(int n, Height h, const FieldGrid4& field) {
  Sheet s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = -1.0f + 2.0f * float(i) / float(n), y = -1.0f + 2.0f * float(j) / float(n);
      s.positions.push_back({x, y, h(x, y), 1.0f});
    }
  auto id = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), 0});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1), 0});
    }
  s.build_csr();
  s.samples.resize(s.positions.size());
  s.velocity.resize(s.positions.size());
  sample_vertices_cpu(field, s.positions, s.samples, 1);
  vertex_velocities_cpu(s.view(), s.samples, s.velocity, 1);
  return s;
}

/// The border of the n×n sheet held (zero filter), the rest free.
std::vector<glm::dmat3> hold_border(int n) {
  std::vector<glm::dmat3> f;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) f.push_back(i == 0 || j == 0 || i == n || j == n ? glm::dmat3(0.0) : glm::dmat3(1.0));
  return f;
}

std::vector<glm::dvec3> solve(const Sheet& s, double dt, const std::vector<glm::dmat3>& filter, int threads = 2) {
  std::vector<glm::dvec3> d(s.positions.size(), glm::dvec3(0.0));
  ImplicitStepOptions o;
  o.threads = threads;
  o.tolerance = 1e-10;
  o.max_iterations = 2000;
  implicit_step(s.view(), s.samples, s.velocity, dt, filter, d, o);
  return d;
}

double bump(float x, float y) { return 0.2 * std::exp(-4.0 * (double(x) * x + double(y) * y)); }

}  // namespace

// For dt → 0 the step is the explicit one, dt·v.
TEST(ImplicitStep, SmallStepIsTheExplicitStep) {
  const FieldGrid4 field = linear_field(1.0f, {0.1f, -0.2f, 0.3f});
  const Sheet s = sheet(8, [](float x, float y) { return float(bump(x, y)); }, field);
  const double dt = 1e-7;
  const std::vector<glm::dvec3> d = solve(s, dt, hold_border(8));
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (hold_border(8)[i] == glm::dmat3(0.0)) continue;
    const glm::dvec3 explicit_step = dt * glm::dvec3(glm::vec3(s.velocity[i]));
    EXPECT_LT(glm::length(d[i] - explicit_step), 1e-3 * glm::length(explicit_step) + 1e-15) << "vertex " << i;
  }
}

// A flat sheet in a linear field whose gradient lies in its plane does not move (the paper's
// claim for equation 3), however large the step: d = 0 is the solution when v = 0.
TEST(ImplicitStep, PlanarSheetInAnInPlaneGradientStays) {
  const FieldGrid4 field = linear_field(2.0f, {0.5f, -0.3f, 0.0f});
  const Sheet s = sheet(6, [](float, float) { return 0.0f; }, field);
  for (double dt : {0.01, 1.0, 100.0}) {
    const std::vector<glm::dvec3> d = solve(s, dt, hold_border(6));
    for (std::size_t i = 0; i < d.size(); ++i) EXPECT_LT(glm::length(d[i]), 1e-5) << "dt " << dt << " vertex " << i;
  }
}

// The held vertices do not move; a filter onto a line keeps the motion on it.
TEST(ImplicitStep, MotionStaysInTheFilter) {
  const FieldGrid4 field = linear_field(1.0f, {0.0f, 0.0f, 0.5f});
  const Sheet s = sheet(6, [](float x, float y) { return float(bump(x, y)); }, field);
  std::vector<glm::dmat3> filter = hold_border(6);
  const glm::dvec3 u = glm::normalize(glm::dvec3(1.0, 1.0, 0.0));
  filter[24] = glm::outerProduct(u, u);  // the centre vertex (3, 3) moves only along u
  const std::vector<glm::dvec3> d = solve(s, 0.5, filter);
  for (std::size_t i = 0; i < d.size(); ++i)
    if (filter[i] == glm::dmat3(0.0)) {
      EXPECT_EQ(d[i], glm::dvec3(0.0)) << "vertex " << i;
    }
  EXPECT_LT(glm::length(d[24] - glm::dot(d[24], u) * u), 1e-9);
}

// The step lowers E to first order: d · ∇E = −d·(M v) < 0; and it does not shrink with the
// triangles: the bump's centre moves about as far on a 4 times finer sheet at the same dt
// (the explicit step would have to shrink 16 times to stay stable there).
TEST(ImplicitStep, DescentWhoseLengthDoesNotShrinkWithTheTriangles) {
  const FieldGrid4 field = linear_field(1.0f, {0.0f, 0.0f, 0.0f});
  double centre_move[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    const int n = k == 0 ? 8 : 32;
    const Sheet s = sheet(n, [](float x, float y) { return float(bump(x, y)); }, field);
    const std::vector<glm::dvec3> d = solve(s, 0.05, hold_border(n));
    double descent = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) descent += glm::dot(d[i], glm::dvec3(glm::vec3(s.velocity[i]))) * s.velocity[i].w;
    EXPECT_GT(descent, 0.0);
    const std::size_t centre = std::size_t(n / 2) * (n + 1) + std::size_t(n / 2);
    centre_move[k] = -d[centre].z;
    EXPECT_GT(centre_move[k], 0.0);  // the bump flattens
    EXPECT_LT(centre_move[k], 0.2);  // and does not overshoot the plane
  }
  EXPECT_NEAR(centre_move[1], centre_move[0], 0.3 * centre_move[0]);
}

// The same bytes for any thread count.
TEST(ImplicitStep, DeterministicForAnyThreadCount) {
  const FieldGrid4 field = linear_field(1.0f, {0.2f, 0.1f, 0.4f});
  const Sheet s = sheet(70, [](float x, float y) { return float(bump(x, y)); }, field);  // > 4096 vertices: chunked
  const std::vector<glm::dvec3> a = solve(s, 0.3, hold_border(70), 1), b = solve(s, 0.3, hold_border(70), 2),
                                c = solve(s, 0.3, hold_border(70), 5);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::dvec3)));
  EXPECT_EQ(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(glm::dvec3)));
}
