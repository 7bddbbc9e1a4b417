// The velocity of equation 3: the checks docs/DESIGN.md ("The velocity") names.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "flow/velocity.hpp"
#include "flow_test_support.hpp"

using namespace fracref;
using fracref::test::linear_field;

namespace {

using Mesh = fracref::test::FlatMesh;

/// A fan of `n` triangles around vertex 0 with rim vertices at the given heights.
Mesh fan(int n, const std::vector<float>& heights, float radius_wobble) {
  Mesh m;
  m.positions.push_back({0.1f, -0.05f, 0.0f, 1.0f});
  for (int k = 0; k < n; ++k) {
    float a = 2.0f * float(M_PI) * k / n + 0.1f * std::sin(3.0f * k);
    float r = 1.0f + radius_wobble * std::cos(2.0f * k + 1.0f);
    m.positions.push_back({r * std::cos(a), r * std::sin(a), heights[k % heights.size()], 1.0f});
  }
  for (int k = 0; k < n; ++k) m.faces.push_back({0u, 1u + k, 1u + (k + 1) % n, 0u});
  m.build_csr();
  return m;
}

std::vector<glm::vec4> velocities(const Mesh& m, const FieldGrid4& f) {
  std::vector<glm::vec4> s(m.positions.size()), v(m.positions.size());
  sample_vertices_cpu(f, m.positions, s);
  vertex_velocities_cpu(m.view(), s, v);
  return v;
}

}  // namespace

TEST(FlowVelocity, ConstantFieldGivesCotangentMeanCurvatureNormal) {
  Mesh m = fan(7, {0.3f, -0.2f, 0.25f, 0.0f, -0.35f, 0.1f, 0.4f}, 0.2f);
  glm::vec4 v = velocities(m, linear_field(1.0f, glm::vec3(0.0f)))[0];
  // Meyer et al. 2002: ∇A_i = ½ Σ_j (cot α_ij + cot β_ij)(x_i − x_j); velocity = −∇A / M_i.
  glm::dvec3 xi(m.positions[0]), grad(0.0);
  double mass = 0.0;
  const int n = 7;
  for (int k = 0; k < n; ++k) {
    glm::dvec3 xj(m.positions[1 + k]), prev(m.positions[1 + (k + n - 1) % n]), next(m.positions[1 + (k + 1) % n]);
    auto cot = [](glm::dvec3 u, glm::dvec3 w) { return glm::dot(u, w) / glm::length(glm::cross(u, w)); };
    double cot_a = cot(xi - prev, xj - prev), cot_b = cot(xi - next, xj - next);
    grad += 0.5 * (cot_a + cot_b) * (xi - xj);
    mass += glm::length(glm::cross(xj - xi, next - xi)) / 6.0;
  }
  glm::dvec3 expected = -grad / mass;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(v[a], expected[a], 1e-4 * glm::length(expected)) << "axis " << a;
  EXPECT_NEAR(v.w, mass, 1e-6);
}

TEST(FlowVelocity, PlanarFanWithLinearInPlaneFieldDoesNotMove) {
  Mesh m = fan(9, {0.0f}, 0.3f);
  glm::vec4 v = velocities(m, linear_field(2.0f, glm::vec3(0.7f, -0.4f, 0.0f)))[0];
  EXPECT_LT(glm::length(glm::vec3(v)), 1e-5f);
}

TEST(FlowVelocity, LinearFieldAcrossThePlaneMovesAlongMinusGradient) {
  Mesh m = fan(9, {0.0f}, 0.3f);
  glm::vec4 v = velocities(m, linear_field(2.0f, glm::vec3(0.0f, 0.0f, 0.5f)))[0];
  // Planar fan: the area term cancels, the field term is −(1/M)Σ(A_j/3)∇ψ = −∇ψ.
  EXPECT_NEAR(v.x, 0.0f, 1e-5f);
  EXPECT_NEAR(v.y, 0.0f, 1e-5f);
  EXPECT_NEAR(v.z, -0.5f, 1e-5f);
}

TEST(FlowVelocity, NonManifoldVertexSumsEveryIncidentFaceOnce) {
  // Three half-planes meeting along the x axis (a T-junction seen end-on); vertex 0 on the junction.
  Mesh m;
  m.positions = {{0, 0, 0, 1}, {1, 0, 0, 1}, {-1, 0, 0, 1}, {0, 1, 0, 1}, {0, -1, 0.2f, 1}, {0, 0, 1, 1}};
  m.faces = {{0, 1, 3, 0}, {0, 3, 2, 0}, {0, 4, 1, 0}, {0, 2, 4, 0}, {0, 5, 1, 0}, {0, 2, 5, 0}};
  m.build_csr();
  glm::vec4 v = velocities(m, linear_field(1.0f, glm::vec3(0.0f)))[0];
  float mass = 0.0f;
  for (auto& f : m.faces) {
    glm::vec3 a(m.positions[f.x]), b(m.positions[f.y]), c(m.positions[f.z]);
    mass += glm::length(glm::cross(b - a, c - a)) / 6.0f;
  }
  EXPECT_NEAR(v.w, mass, 1e-6f);
  EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
}

TEST(FlowVelocity, SmallStepDecreasesTheEnergy) {
  Mesh m = fan(8, {0.3f, -0.2f, 0.25f, 0.0f, -0.35f, 0.1f, 0.4f, -0.1f}, 0.2f);
  FieldGrid4 f = linear_field(3.0f, glm::vec3(0.2f, -0.3f, 0.6f));
  std::vector<glm::vec4> s(m.positions.size()), v(m.positions.size());
  sample_vertices_cpu(f, m.positions, s);
  vertex_velocities_cpu(m.view(), s, v);
  double e0 = surface_energy(m.view(), s);
  Mesh moved = m;
  for (std::size_t i = 0; i < m.positions.size(); ++i) moved.positions[i] += 1e-3f * glm::vec4(glm::vec3(v[i]), 0.0f);
  sample_vertices_cpu(f, moved.positions, s);
  EXPECT_LT(surface_energy(moved.view(), s), e0);
}
