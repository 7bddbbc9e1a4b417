#include "pipeline/strength.hpp"

#include <cmath>
#include <limits>
#include <thread>

#include "geom/bvh.hpp"

namespace fracref {

Grid3 distance_grid(const Grid3& grid, const std::vector<glm::dvec3>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads) {
  Bvh bvh = build_bvh(positions, triangles);
  Grid3 out = grid;
  out.values.assign(grid.size(), 0.0f);
  // The triangle nearest to the node before it in its row is usually nearest to this node too,
  // or nearly: its distance (a little over, so that it is found again) bounds the search, which
  // then skips most of the tree (closest_point's answer is the same).
  auto work = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < grid.dims.y; ++y) {
        std::uint32_t before = 0;
        for (unsigned x = 0; x < grid.dims.x; ++x) {
          const glm::dvec3 p = grid.node_position(x, y, z);
          ClosestPoint c;
          if (x > 0) {
            const auto& t = triangles[before];
            const double d2 = closest_point_on_triangle(p, positions[t[0]], positions[t[1]], positions[t[2]]).squared_distance;
            c = closest_point(bvh, p, d2 * (1.0 + 1e-9) + 1e-300);
          }
          if (!(c.squared_distance < std::numeric_limits<double>::infinity())) c = closest_point(bvh, p);
          before = c.triangle;
          out.values[grid.index(x, y, z)] = float(std::sqrt(c.squared_distance));
        }
      }
  };
  if (threads <= 1) {
    work(0, grid.dims.z);
  } else {
    std::thread other(work, 0u, grid.dims.z / 2);
    work(grid.dims.z / 2, grid.dims.z);
    other.join();
  }
  return out;
}

Grid3 modified_field(const Grid3& zeta, const Grid3& distance, const WeightsSpec& w, double diagonal) {
  Grid3 psi = zeta;
  for (std::size_t i = 0; i < psi.values.size(); ++i)
    psi.values[i] = float(w.strength * zeta.values[i] + w.distance * distance.values[i] / diagonal + w.offset);
  return psi;
}

}  // namespace fracref
