#pragma once
// The angle of a corner between two rays, the one formula every stage uses.
#include <cmath>

#include <glm/glm.hpp>

namespace fracref {

/// The angle at `a` between the rays to `b` and to `c`, in [0, π] radians: atan2 of |u × v| and
/// u · v, accurate near 0 and π (where acos of the cosine is not); 0 when a ray has length 0.
inline double corner_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 u = b - a, v = c - a;
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

}  // namespace fracref
