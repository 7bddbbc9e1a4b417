// collar_rim (refine/rim_collar.hpp).
#include "refine/rim_collar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace

std::size_t collar_rim(FractureSurface& s, RefinementTree& tree, const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                       const CollarOptions& o) {
  std::size_t made = 0;
  std::vector<char> done(s.positions.size(), 0);  // per rim vertex: its edges were judged
  for (int pass = 0; pass < o.passes; ++pass) {
    std::vector<SplitRequest> requests;
    std::vector<glm::vec3> positions;
    std::vector<char> touched(s.faces.size(), 0);
    for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
      if (s.edge_special[e] != kEdgeRegular) continue;
      const glm::uvec2 ab = s.edges[e];
      const bool rim_a = ab.x < rim.on_b.size() && rim.on_b[ab.x], rim_b = ab.y < rim.on_b.size() && rim.on_b[ab.y];
      if (rim_a == rim_b) continue;  // interior, or a chord (split_rim_chords splits those)
      const std::uint32_t p = rim_a ? ab.x : ab.y, c = rim_a ? ab.y : ab.x;
      const glm::dvec3 n = rim::location_normal(exterior, rim.at[p]);
      const glm::dvec3 d = at(s, c) - at(s, p);
      const double length = glm::length(d);
      if (!(length > 0.0) || glm::dot(d, n) < -o.grazing * length) continue;
      bool free = true;
      for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) free = free && !touched[s.ef_faces[k]];
      if (!free) continue;
      for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) touched[s.ef_faces[k]] = 1;
      const double t = std::min(0.25, o.reach * shortest_rim_edge(s, p) / length);
      glm::dvec3 x = at(s, p) + t * d;
      x -= n * (glm::dot(x - at(s, p), n) + o.depth * t * length);
      const float tp = float(rim_a ? t : 1.0 - t);
      requests.push_back({SplitRequest::kEdge, e, glm::vec3(1.0f - tp, tp, 0.0f)});
      positions.push_back(glm::vec3(x));
    }
    if (requests.empty()) break;
    made += apply_splits(s, tree, requests, &positions);
  }
  (void)done;
  return made;
}

}  // namespace fracref
