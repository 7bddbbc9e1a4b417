#include "refine/junction_order.hpp"

#include <vector>

#include "surface/radial_order.hpp"

namespace fracref {
namespace {

glm::dvec3 at_vertex(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

std::uint32_t opposite(const glm::uvec4& f, std::uint32_t a, std::uint32_t b) { return f.x + f.y + f.z - a - b; }

template <class Where>
std::vector<std::uint32_t> order_about(const FractureSurface& s, std::uint32_t e, const glm::dvec3& p,
                                       const glm::dvec3& q, Where where) {
  return from_lowest(radial_order_about(s, e, p, q, where));
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

bool flip_keeps_junction_order(const FractureSurface& s, std::uint32_t e, glm::uvec2 cd, glm::uvec2 ff,
                               std::array<std::uint32_t, 4>& junctions) {
  junctions.fill(kNoEdge);
  int found = 0;
  for (int side = 0; side < 2; ++side) {
    const std::uint32_t f = ff[side];
    const glm::dvec3 turned_to = at_vertex(s, cd[1 - side]);
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t g = s.face_edges[3 * f + c];
      if (g == e || s.edge_special[g] != kEdgeNonManifold) continue;
      if (!neighbour_keeps_order(s, g, f, turned_to)) return false;
      junctions[std::size_t(found++)] = g;
    }
  }
  return true;
}

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
