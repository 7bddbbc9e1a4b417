#pragma once
// The order of the faces around an edge of S, as rebuild_adjacency reads it from the geometry to
// tell the pieces apart at a junction (non-manifold) edge. Shared by the side components, the flow
// step's guard and the refiner's split check, so that all three judge one and the same order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "surface/fracture_surface.hpp"

namespace fracref {

/// The faces of edge e in counter-clockwise order about the axis p → q, by the angle of each
/// face's opposite vertex, at where(face), in the plane perpendicular to the axis, measured from
/// the first face of e (ascending ids) whose perpendicular is not zero; ties by face id.
/// rebuild_adjacency uses it with p, q the edge's ends (smaller id first) at their positions.
/// \pre adjacency current (the edge's faces).
template <class Where>
std::vector<std::uint32_t> radial_order_about(const FractureSurface& s, std::uint32_t e, const glm::dvec3& p,
                                              const glm::dvec3& q, Where where) {
  const glm::dvec3 t = q - p;
  const double tt = glm::dot(t, t);
  std::vector<std::pair<double, std::uint32_t>> keyed;
  glm::dvec3 e1(0.0), e2(0.0);
  for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
    const std::uint32_t f = s.ef_faces[k];
    const glm::dvec3 u = where(f) - p;
    const glm::dvec3 perp = tt > 0.0 ? u - t * (glm::dot(u, t) / tt) : glm::dvec3(0.0);
    if (e1 == glm::dvec3(0.0) && glm::dot(perp, perp) > 0.0) {
      e1 = glm::normalize(perp);
      e2 = glm::cross(t / std::sqrt(tt), e1);
    }
    keyed.emplace_back(std::atan2(glm::dot(perp, e2), glm::dot(perp, e1)), f);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order;
  for (const auto& k : keyed) order.push_back(k.second);
  return order;
}

/// The same cyclic order written from its lowest face id, so that two orders of the same faces
/// compare equal exactly when no face passed another.
inline std::vector<std::uint32_t> from_lowest(std::vector<std::uint32_t> order) {
  std::rotate(order.begin(), std::min_element(order.begin(), order.end()), order.end());
  return order;
}

}  // namespace fracref
