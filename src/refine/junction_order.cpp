#include "refine/junction_order.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fracref {
namespace {

glm::dvec3 at_vertex(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

std::uint32_t opposite(const glm::uvec4& f, std::uint32_t a, std::uint32_t b) { return f.x + f.y + f.z - a - b; }

// The faces around junction edge e in their cyclic order about the axis p → q (rotated to start
// at the lowest face id), each face's opposite vertex at `where(face)`.
template <class Where>
std::vector<std::uint32_t> order_about(const FractureSurface& s, std::uint32_t e, const glm::dvec3& p,
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
  std::rotate(order.begin(), std::min_element(order.begin(), order.end()), order.end());
  return order;
}

std::vector<std::uint32_t> order_now(const FractureSurface& s, std::uint32_t e) {
  const glm::uvec2 ab = s.edges[e];
  return order_about(s, e, at_vertex(s, ab.x), at_vertex(s, ab.y),
                     [&](std::uint32_t f) { return at_vertex(s, opposite(s.faces[f], ab.x, ab.y)); });
}

// The split edge itself: its faces keep their opposite vertices, about two shorter axes.
bool halves_keep_order(const FractureSurface& s, std::uint32_t e, const glm::dvec3& m) {
  const glm::uvec2 ab = s.edges[e];
  const std::vector<std::uint32_t> before = order_now(s, e);
  auto where = [&](std::uint32_t f) { return at_vertex(s, opposite(s.faces[f], ab.x, ab.y)); };
  return order_about(s, e, at_vertex(s, ab.x), m, where) == before &&
         order_about(s, e, m, at_vertex(s, ab.y), where) == before;
}

// Another junction edge g of a face f that the split cuts: f's child on g has m opposite g.
bool neighbour_keeps_order(const FractureSurface& s, std::uint32_t g, std::uint32_t f, const glm::dvec3& m) {
  const glm::uvec2 pq = s.edges[g];
  auto where = [&](std::uint32_t h) { return h == f ? m : at_vertex(s, opposite(s.faces[h], pq.x, pq.y)); };
  return order_about(s, g, at_vertex(s, pq.x), at_vertex(s, pq.y), where) == order_now(s, g);
}

}  // namespace

bool split_keeps_junction_order(const FractureSurface& s, const SplitRequest& r, const glm::vec3& at) {
  const std::uint32_t e = r.element;
  const glm::dvec3 m(at);
  if (s.edge_special[e] == kEdgeNonManifold && !halves_keep_order(s, e, m)) return false;
  for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
    const std::uint32_t f = s.ef_faces[k];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t g = s.face_edges[3 * f + c];
      if (g != e && s.edge_special[g] == kEdgeNonManifold && !neighbour_keeps_order(s, g, f, m)) return false;
    }
  }
  return true;
}

}  // namespace fracref
