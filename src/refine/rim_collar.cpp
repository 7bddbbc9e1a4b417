// collar_rim (refine/rim_collar.hpp).
#include "refine/rim_collar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "geom/bvh.hpp"
#include "geom/face_guard.hpp"

namespace fracref {
namespace {

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

// The rim vertex's shortest rim edge (infinity when it has none).
double shortest_rim_edge(const FractureSurface& s, std::uint32_t p) {
  double shortest = std::numeric_limits<double>::infinity();
  for (std::uint32_t k = s.vf_offsets[p]; k < s.vf_offsets[p + 1]; ++k) {
    const std::uint32_t f = s.vf_faces[k];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t e = s.face_edges[3 * f + std::uint32_t(c)];
      if (s.edge_special[e] == kEdgeBoundary && (s.edges[e].x == p || s.edges[e].y == p))
        shortest = std::min(shortest, glm::length(at(s, s.edges[e].x) - at(s, s.edges[e].y)));
    }
  }
  return shortest;
}

// Whether q lies within `gap` of the third corner of a face on edge e.
bool lands_by_a_corner(const FractureSurface& s, std::uint32_t e, const glm::dvec3& q, double gap) {
  const glm::uvec2 ab = s.edges[e];
  for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
    const glm::uvec4 f = s.faces[s.ef_faces[k]];
    if (glm::length(at(s, f.x + f.y + f.z - ab.x - ab.y) - q) < gap) return true;
  }
  return false;
}

}  // namespace

std::size_t collar_rim(FractureSurface& s, RefinementTree& tree, const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                       const CollarOptions& o) {
  std::size_t made = 0;
  for (int pass = 0; pass < o.passes; ++pass) {
    std::vector<SplitRequest> requests;
    std::vector<glm::vec3> positions;
    std::vector<char> touched(s.faces.size(), 0);
    const std::vector<glm::dvec3> x = double_positions(s);
    std::vector<TriangleIds> faces;
    for (const glm::uvec4& f : s.faces) faces.push_back({f.x, f.y, f.z});
    FaceGuard guard(x, faces);
    for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
      if (s.edge_special[e] == kEdgeBoundary) continue;
      const glm::uvec2 ab = s.edges[e];
      const bool rim_a = ab.x < rim.on_b.size() && rim.on_b[ab.x], rim_b = ab.y < rim.on_b.size() && rim.on_b[ab.y];
      if (rim_a == rim_b) continue;  // interior, or a chord (split_rim_chords splits those)
      const std::uint32_t p = rim_a ? ab.x : ab.y, c = rim_a ? ab.y : ab.x;
      // Judged against each triangle of B that holds p (the pieces stage's rule, exterior_contact.hpp).
      const std::vector<std::uint32_t> holders = rim::location_faces(exterior, rim.at[p]);
      const glm::dvec3 d = at(s, c) - at(s, p);
      const double length = glm::length(d);
      double rise = -1.0;
      for (std::uint32_t h : holders) rise = std::max(rise, glm::dot(d, exterior.face_normals[h]) / length);
      if (!(length > 0.0) || rise < -o.grazing) continue;
      bool free = true;
      for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) free = free && !touched[s.ef_faces[k]];
      if (!free) continue;
      const double t = std::min(0.25, o.reach * shortest_rim_edge(s, p) / length);
      glm::dvec3 q = at(s, p) + t * d;
      for (int round = 0; round < 3; ++round)
        for (std::uint32_t h : holders) {
          const glm::dvec3 n = exterior.face_normals[h];
          const double over = glm::dot(q - at(s, p), n) + o.depth * t * length;
          if (over > 0.0) q -= n * over;
        }
      q = stored_position(q);
      if (!point_in_mesh(exterior.bvh, q)) continue;
      // Nor where the new vertex would land by the third corner of a face on the edge: that corner
      // lies near the edge (two rim vertices' collars zig-zagging between them, pass after pass),
      // and the split would leave a needle with an edge a float's rounding long.
      if (lands_by_a_corner(s, e, q, o.min_gap * length)) continue;
      // The new faces must meet no other face of S (exact).
      const std::uint32_t id = guard.add_vertex(q);
      std::vector<TriangleIds> made_faces;
      std::vector<std::uint32_t> replaced;
      for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
        const glm::uvec4 f = s.faces[s.ef_faces[k]];
        const std::uint32_t z = f.x + f.y + f.z - ab.x - ab.y;
        const bool forward = (f.x == ab.x && f.y == ab.y) || (f.y == ab.x && f.z == ab.y) || (f.z == ab.x && f.x == ab.y);
        const std::uint32_t u = forward ? ab.x : ab.y, w = forward ? ab.y : ab.x;
        made_faces.push_back({u, id, z});
        made_faces.push_back({id, w, z});
        replaced.push_back(s.ef_faces[k]);
      }
      if (!guard.clear(made_faces, replaced)) continue;
      guard.accept(made_faces, replaced);
      for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) touched[s.ef_faces[k]] = 1;
      const float tp = float(rim_a ? t : 1.0 - t);
      requests.push_back({SplitRequest::kEdge, e, glm::vec3(1.0f - tp, tp, 0.0f)});
      positions.push_back(glm::vec3(q));
    }
    if (requests.empty()) break;
    made += apply_splits(s, tree, requests, &positions);
  }
  return made;
}

}  // namespace fracref
