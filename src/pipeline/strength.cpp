#include "pipeline/strength.hpp"

#include <thread>

#include "geom/bvh.hpp"

namespace fracref {

Grid3 distance_grid(const Grid3& grid, const std::vector<glm::dvec3>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads) {
  Bvh bvh = build_bvh(positions, triangles);
  Grid3 out = grid;
  out.values.assign(grid.size(), 0.0f);
  auto work = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < grid.dims.y; ++y)
        for (unsigned x = 0; x < grid.dims.x; ++x)
          out.values[grid.index(x, y, z)] = float(std::sqrt(closest_point(bvh, grid.node_position(x, y, z)).squared_distance));
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
