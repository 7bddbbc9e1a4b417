#pragma once
// A scalar field sampled on a regular 3D grid: the strength field, the distance field and
// every level of the Gaussian pyramid use it.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// Values at the nodes of a regular grid, x fastest: index = x + nx*(y + ny*z).
/// Node (i,j,k) sits at world position origin + cell * (i,j,k).
struct Grid3 {
  glm::uvec3 dims{0, 0, 0};
  glm::dvec3 origin{0.0};
  double cell = 1.0;
  std::vector<float> values;

  std::size_t size() const { return std::size_t(dims.x) * dims.y * dims.z; }
  std::size_t index(unsigned x, unsigned y, unsigned z) const {
    return x + std::size_t(dims.x) * (y + std::size_t(dims.y) * z);
  }
  float at(unsigned x, unsigned y, unsigned z) const { return values[index(x, y, z)]; }
  glm::dvec3 node_position(unsigned x, unsigned y, unsigned z) const {
    return origin + cell * glm::dvec3(x, y, z);
  }
};

}  // namespace fracref
