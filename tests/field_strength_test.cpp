// The modified strength field ψ (paper 4.2): the distance grid to the coarse fracture surface
// and ψ = w_ζ·ζ + w_d·d/diagonal + ψ0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "field/strength.hpp"
#include "geom/bvh.hpp"
#include "geom/shapes.hpp"

using namespace fracref;

TEST(FieldStrength, DistanceAndModifiedField) {
  Grid3 g;
  g.dims = {5, 5, 5};
  g.origin = glm::dvec3(0.0);
  g.cell = 0.25;
  g.values.assign(g.size(), 0.5f);
  // One big triangle in the plane z = 0.5 covering the grid's xy range.
  Grid3 d = distance_grid(g, {{-1, -1, 0.5}, {4, -1, 0.5}, {-1, 4, 0.5}}, {{0, 1, 2}}, 2);
  for (unsigned z = 0; z < 5; ++z) EXPECT_NEAR(d.at(2, 2, z), std::abs(0.25 * z - 0.5), 1e-6) << z;
  FieldWeights w;
  w.strength = 2.0;
  w.distance = 4.0;
  w.offset = 0.1;
  Grid3 psi = modified_field(g, d, w, 2.0);
  EXPECT_NEAR(psi.at(1, 1, 0), 2.0 * 0.5 + 4.0 * 0.5 / 2.0 + 0.1, 1e-6);
  EXPECT_NEAR(psi.at(1, 1, 2), 2.0 * 0.5 + 0.1, 1e-6);
}

// distance_grid shares candidate lists between nearby nodes; its values must be exactly those of
// the plain definition, the least squared distance to any triangle, on a mesh of uneven
// triangles and a grid reaching far outside it (nodes near it, inside it and far from it).
TEST(FieldStrength, DistanceGridEqualsTheNearestTriangleEverywhere) {
  TriangleSoup mesh = make_uv_sphere({0.3, -0.2, 0.1}, 0.8, 9, 14);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (auto& p : mesh.positions) p += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
  Grid3 g;
  g.dims = {13, 10, 11};
  g.origin = glm::dvec3(-2.0, -1.7, -1.9);
  g.cell = 0.37;
  g.values.assign(g.size(), 0.0f);
  const Grid3 d = distance_grid(g, mesh.positions, mesh.triangles, 2);
  for (unsigned z = 0; z < g.dims.z; ++z)
    for (unsigned y = 0; y < g.dims.y; ++y)
      for (unsigned x = 0; x < g.dims.x; ++x) {
        const glm::dvec3 p = g.node_position(x, y, z);
        double best = std::numeric_limits<double>::infinity();
        for (const auto& t : mesh.triangles)
          best = std::min(best, closest_point_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]],
                                                          mesh.positions[t[2]]).squared_distance);
        ASSERT_EQ(d.at(x, y, z), float(std::sqrt(best))) << x << " " << y << " " << z;
      }
}
