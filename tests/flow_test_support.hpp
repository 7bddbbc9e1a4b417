#pragma once
// A field grid the flow tests share.
#include <vector>

#include "field/field_sampler.hpp"

namespace fracref::test {

/// A field grid holding ψ(x) = c + g·x exactly (trilinear interpolation of a linear function is exact).
inline FieldGrid4 linear_field(float c, glm::vec3 g) {
  FieldGrid4 f;
  f.dims = {9, 9, 9};
  f.origin = glm::dvec3(-2.0);
  f.cell = 0.5;
  for (unsigned z = 0; z < 9; ++z)
    for (unsigned y = 0; y < 9; ++y)
      for (unsigned x = 0; x < 9; ++x) {
        const glm::vec3 p = glm::vec3(f.origin) + float(f.cell) * glm::vec3(x, y, z);
        f.values.push_back(glm::vec4(c + glm::dot(g, p), g));
      }
  return f;
}

}  // namespace fracref::test
