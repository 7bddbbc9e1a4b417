// The tangential relaxation of the sheets (refine/relaxation.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "refine/relaxation.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

std::uint32_t grid_id(int n, int i, int j) { return std::uint32_t(j * n + i); }

std::vector<glm::dvec3> relaxed(const FractureSurface& s, std::vector<glm::dvec3> d, double fraction, int threads = 1) {
  add_tangential_relaxation(s, s.positions, d, {.fraction = fraction, .threads = threads});
  return d;
}

// The 5x5 grid with its middle vertex pushed off its ring's centroid: half the way back, in the
// sheet's plane.
TEST(Relaxation, AVertexOffItsRingsCentroidMovesTowardItAlongTheSheet) {
  FractureSurface s = example_sheet(5);
  const std::uint32_t mid = grid_id(5, 2, 2);
  std::vector<glm::dvec3> d(s.positions.size(), glm::dvec3(0.0));
  d[mid] = glm::dvec3(0.3, 0.0, 0.0);  // the flow's motion: the relaxation acts at x + d
  const std::vector<glm::dvec3> r = relaxed(s, d, 0.5);
  // Its ring's corners, counted once per face, average to the grid point (2, 2) plus a skew from
  // the diagonals; the move is half of that offset from (2.3, 2).
  glm::dvec3 centroid(0.0);
  int corners = 0;
  for (std::uint32_t k = s.vf_offsets[mid]; k < s.vf_offsets[mid + 1]; ++k)
    for (int c = 0; c < 3; ++c)
      if (const std::uint32_t v = s.faces[s.vf_faces[k]][c]; v != mid)
        centroid += glm::dvec3(glm::vec3(s.positions[v])), ++corners;
  centroid /= double(corners);
  const glm::dvec3 at = glm::dvec3(glm::vec3(s.positions[mid])) + d[mid];
  const glm::dvec3 expected = d[mid] + 0.5 * glm::dvec3(centroid.x - at.x, centroid.y - at.y, 0.0);
  EXPECT_NEAR(r[mid].x, expected.x, 1e-12);
  EXPECT_NEAR(r[mid].y, expected.y, 1e-12);
  EXPECT_EQ(r[mid].z, 0.0);  // along the sheet only
  EXPECT_LT(r[mid].x, d[mid].x);
}

// A vertex raised out of a flat sheet: its ring's centroid lies below it, along its normal, which
// the relaxation leaves to the flow.
TEST(Relaxation, ItDoesNotMoveAVertexAlongItsNormal) {
  FractureSurface s = example_sheet(5);
  const std::uint32_t mid = grid_id(5, 2, 2);
  std::vector<glm::dvec3> d(s.positions.size(), glm::dvec3(0.0));
  d[mid].z = 0.5;
  const std::vector<glm::dvec3> r = relaxed(s, d, 1.0);
  glm::dvec3 normal(0.0);
  const auto y = [&](std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])) + d[v]; };
  for (std::uint32_t k = s.vf_offsets[mid]; k < s.vf_offsets[mid + 1]; ++k) {
    const glm::uvec4 f = s.faces[s.vf_faces[k]];
    normal += glm::cross(y(f.y) - y(f.x), y(f.z) - y(f.x));
  }
  normal = glm::normalize(normal);
  EXPECT_NEAR(glm::dot(r[mid] - d[mid], normal), 0.0, 1e-12);
}

TEST(Relaxation, RimAndJunctionVerticesKeepTheirMotion) {
  const FractureSurface s = example_t_junction(3);
  std::vector<glm::dvec3> d(s.positions.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = glm::dvec3(0.01 * double(i % 7), -0.02, 0.015 * double(i % 3));
  const std::vector<glm::dvec3> r = relaxed(s, d, 1.0);
  int kept = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (s.vertex_flags[i] & (kVertexBoundary | kVertexNonManifold)) {
      EXPECT_EQ(r[i], d[i]) << "vertex " << i;
      ++kept;
    }
  EXPECT_GT(kept, 0);
}

TEST(Relaxation, OffOrOnAnyThreadCountTheSameMotion) {
  FractureSurface s = example_sheet(9);
  std::vector<glm::dvec3> d(s.positions.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = glm::dvec3(std::sin(double(i)), std::cos(3.0 * double(i)), 0.1 * std::sin(7.0 * double(i))) * 0.2;
  EXPECT_EQ(relaxed(s, d, 0.0), d);
  const std::vector<glm::dvec3> one = relaxed(s, d, 0.5, 1);
  EXPECT_NE(one, d);
  EXPECT_EQ(relaxed(s, d, 0.5, 3), one);
}

}  // namespace
}  // namespace fracref
