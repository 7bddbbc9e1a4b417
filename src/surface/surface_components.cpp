// Side components of the fracture surface: the regions of the volume next to S, found by a flood
// fill over face sides. Each region is one piece (or part of one), which is what lets validate()
// check the piece labels against the geometry.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "surface/radial_order.hpp"
#include "surface/surface_internal.hpp"

namespace fracref::surface_detail {
namespace {

std::uint32_t opposite_vertex(const glm::uvec4& face, glm::uvec2 edge) {
  for (int i = 0; i < 3; ++i)
    if (face[i] != edge.x && face[i] != edge.y) return face[i];
  return face[0];
}

// Faces of a non-manifold edge in counter-clockwise order around the axis a -> b (a < b).
std::vector<std::uint32_t> radial_order(const FractureSurface& s, std::uint32_t e) {
  const glm::uvec2 ab = s.edges[e];
  return radial_order_about(s, e, glm::dvec3(s.positions[ab.x]), glm::dvec3(s.positions[ab.y]),
                            [&](std::uint32_t f) { return glm::dvec3(s.positions[opposite_vertex(s.faces[f], ab)]); });
}

void join_regular(const FractureSurface& s, std::uint32_t e, std::vector<SideJoin>& out) {
  const std::uint32_t f = s.ef_faces[s.ef_offsets[e]], g = s.ef_faces[s.ef_offsets[e] + 1];
  const bool consistent = traverses_forward(s, f, e) != traverses_forward(s, g, e);
  out.push_back({e, face_side(f, false), face_side(g, !consistent)});
  out.push_back({e, face_side(f, true), face_side(g, consistent)});
}

// A face traversing a -> b has its normal along axis x (opposite vertex), i.e. pointing to the
// counter-clockwise wedge: its front faces the wedge after it, its back the wedge before it.
void join_non_manifold(const FractureSurface& s, std::uint32_t e, std::vector<SideJoin>& out) {
  const std::vector<std::uint32_t> order = radial_order(s, e);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t f = order[k], g = order[(k + 1) % order.size()];
    out.push_back({e, face_side(f, !traverses_forward(s, f, e)), face_side(g, traverses_forward(s, g, e))});
  }
}

}  // namespace

void side_joins_at(const FractureSurface& s, std::uint32_t e, std::vector<SideJoin>& joins) {
  const std::uint32_t n = s.ef_offsets[e + 1] - s.ef_offsets[e];
  if (n == 2) join_regular(s, e, joins);
  else if (n >= 3) join_non_manifold(s, e, joins);
}

std::vector<SideJoin> side_joins(const FractureSurface& s) {
  std::vector<SideJoin> joins;
  joins.reserve(s.ef_faces.size());
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) side_joins_at(s, e, joins);
  return joins;
}

void build_components(FractureSurface& s) {
  const std::size_t sides = 2 * s.faces.size();
  std::vector<std::uint32_t> parent(sides);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const SideJoin& j : side_joins(s)) {
    const std::uint32_t ra = root(j.a), rb = root(j.b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  // Roots are each component's lowest side, so numbering in side order is deterministic.
  s.side_component.assign(sides, 0);
  s.component_count = 0;
  for (std::uint32_t x = 0; x < sides; ++x) {
    const std::uint32_t r = root(x);
    s.side_component[x] = r == x ? s.component_count++ : s.side_component[r];
  }
}

}  // namespace fracref::surface_detail

namespace fracref {

// From the face's corners alone (the edge table is read in order by the callers): looking the
// edge up in face_edges cost another random access per call, a quarter of validate().
bool traverses_forward(const FractureSurface& s, std::uint32_t f, std::uint32_t e) {
  const glm::uvec4 face = s.faces[f];
  const glm::uvec2 ab = s.edges[e];
  for (int i = 0; i < 3; ++i)
    if (face[i] == ab.x) return face[(i + 1) % 3] == ab.y;
  return false;
}

}  // namespace fracref
