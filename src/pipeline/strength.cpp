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
  // Distance is 1-Lipschitz: a node is at most one cell farther than the node before it in its
  // row, a bound that lets the search skip most of the tree (closest_point's answer is the same).
  auto work = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < grid.dims.y; ++y) {
        double before = std::numeric_limits<double>::infinity();
        for (unsigned x = 0; x < grid.dims.x; ++x) {
          const glm::dvec3 p = grid.node_position(x, y, z);
          const double reach = (before + grid.cell) * (1.0 + 1e-6);
          ClosestPoint c = closest_point(bvh, p, reach * reach);
          if (!(c.squared_distance < std::numeric_limits<double>::infinity())) c = closest_point(bvh, p);
          before = std::sqrt(c.squared_distance);
          out.values[grid.index(x, y, z)] = float(before);
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
