#include "refine/rim_smoothing.hpp"

#include <cmath>
#include <vector>

#include "refine/collisions.hpp"
#include "refine/containment.hpp"
#include "refine/step_guard.hpp"

namespace fracref {
namespace {

// Per rim vertex, its neighbours along the rim: two inside a sheet's rim, one per sheet's rim
// where sheets meet B together (a junction's end, which then moves to the mean of them all, the
// sheets' rims with it); empty for a vertex on fewer than two boundary edges.
std::vector<std::vector<std::uint32_t>> rim_neighbours(const FractureSurface& s) {
  std::vector<std::vector<std::uint32_t>> nb(s.positions.size());
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s.edges[e];
    nb[ab.x].push_back(ab.y), nb[ab.y].push_back(ab.x);
  }
  for (std::vector<std::uint32_t>& n : nb)
    if (n.size() < 2) n.clear();
  return nb;
}

glm::dvec3 point(const std::vector<glm::vec4>& x, std::uint32_t v) { return glm::dvec3(glm::vec3(x[v])); }

glm::dvec3 area_normal(const std::vector<glm::vec4>& x, const glm::uvec4& f) {
  return glm::cross(point(x, f.y) - point(x, f.x), point(x, f.z) - point(x, f.x));
}

// Whether face f keeps its orientation and most of its area from x0 to x1.
bool face_keeps_shape(const glm::uvec4& f, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                      const RimSmoothingOptions& o) {
  const glm::dvec3 n0 = area_normal(x0, f), n1 = area_normal(x1, f);
  const double a0 = glm::length(n0), a1 = glm::length(n1);
  if (a1 < o.min_area_ratio * a0) return false;
  return glm::dot(n0, n1) >= std::cos(glm::radians(o.max_turn_degrees)) * a0 * a1;
}

// The pass's proposed positions: each rim vertex toward its rim neighbours' mean, onto B; not one
// whose target lies far off B for the length of its move (its rim turns round a crease of B,
// whose corner it would cut).
std::vector<glm::vec4> proposed(const std::vector<glm::vec4>& x0, const std::vector<std::vector<std::uint32_t>>& nb,
                                const ExteriorSurface& b, const RimSmoothingOptions& o) {
  std::vector<glm::vec4> x1 = x0;
  for (std::size_t v = 0; v < nb.size(); ++v) {
    if (nb[v].empty()) continue;
    const glm::dvec3 p = point(x0, std::uint32_t(v));
    glm::dvec3 mean(0.0);
    for (const std::uint32_t w : nb[v]) mean += point(x0, w);
    const glm::dvec3 target = p + o.weight * (mean / double(nb[v].size()) - p);
    const glm::dvec3 q = b.closest_point(target);
    if (glm::distance(q, target) <= o.max_off_b * glm::distance(target, p)) x1[v] = glm::vec4(glm::vec3(q), 1.0f);
  }
  return x1;
}

// The cosine of the angle between the normals of edge e's two faces at x, the second's normal
// turned where the faces wind the edge the same way (two sheets' windings may differ).
double crease_cosine(const FractureSurface& s, std::uint32_t e, const std::vector<glm::vec4>& x) {
  const std::uint32_t f = s.ef_faces[s.ef_offsets[e]], g = s.ef_faces[s.ef_offsets[e] + 1];
  const glm::dvec3 nf = area_normal(x, s.faces[f]), ng = area_normal(x, s.faces[g]);
  const double len = glm::length(nf) * glm::length(ng);
  if (len == 0.0) return -1.0;
  return (traverses_forward(s, f, e) == traverses_forward(s, g, e) ? -1.0 : 1.0) * glm::dot(nf, ng) / len;
}

// Whether edge e, between two faces, becomes a sharper crease than max_crease_degrees and than
// it was at x0: two faces that turn apart each within max_turn_degrees can still fold.
bool edge_folds(const FractureSurface& s, std::uint32_t e, const std::vector<glm::vec4>& x0,
                const std::vector<glm::vec4>& x1, const RimSmoothingOptions& o) {
  if (s.ef_offsets[e + 1] - s.ef_offsets[e] != 2) return false;
  const double limit = std::cos(glm::radians(o.max_crease_degrees));
  const double c1 = crease_cosine(s, e, x1);
  return c1 < limit && c1 < crease_cosine(s, e, x0);
}

// Per face of S at its positions, whether it meets B (face_meets_exterior), for the faces with a
// corner that x1 moves (the others: 0).
std::vector<char> faces_meeting_exterior(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x1) {
  std::vector<char> met(s.faces.size(), 0);
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t = s.faces[f];
    if (x1[t.x] != s.positions[t.x] || x1[t.y] != s.positions[t.y] || x1[t.z] != s.positions[t.z])
      met[f] = face_meets_exterior(s, f, b) ? 1 : 0;
  }
  return met;
}

// Holds back (at x0) the moved corners of every face with a moved corner that fails a check at
// x1 (and of its neighbour across an edge that folds). S's positions are x1 as it was on entry
// (face_meets_exterior reads them); smooth_rim sets them once the checks settle.
void hold_bad_faces(FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0,
                    std::vector<glm::vec4>& x1, const std::vector<char>& met, const RimSmoothingOptions& o) {
  s.positions = x1;
  std::vector<std::uint32_t> hold;
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t = s.faces[f];
    if (x1[t.x] == x0[t.x] && x1[t.y] == x0[t.y] && x1[t.z] == x0[t.z]) continue;
    bool bad = !face_keeps_shape(t, x0, x1, o) || (!met[f] && face_meets_exterior(s, f, b));
    for (int k = 0; k < 3 && !bad; ++k) {
      const std::uint32_t e = s.face_edges[3 * f + k];
      if (!edge_folds(s, e, x0, x1, o)) continue;
      bad = true;
      for (std::uint32_t j = s.ef_offsets[e]; j < s.ef_offsets[e + 1]; ++j)
        for (int c = 0; c < 3; ++c) hold.push_back(s.faces[s.ef_faces[j]][c]);
    }
    if (!bad) continue;
    for (int c = 0; c < 3; ++c) hold.push_back(t[c]);
  }
  for (const std::uint32_t v : hold) x1[v] = x0[v];
}

}  // namespace

std::size_t smooth_rim(FractureSurface& s, const ExteriorSurface& b, const RimSmoothingOptions& o) {
  if (o.passes <= 0) return 0;
  const std::vector<std::vector<std::uint32_t>> nb = rim_neighbours(s);
  std::size_t moves = 0;
  for (int pass = 0; pass < o.passes; ++pass) {
    const std::vector<glm::vec4> x0 = s.positions;
    std::vector<glm::vec4> x1 = proposed(x0, nb, b, o);
    const std::vector<char> met = faces_meeting_exterior(s, b, x1);
    // Holding a vertex back changes its faces' shapes, and may expose a collision or a bad face:
    // check both again until x1 stays as it is (each round holds a vertex more or is the last).
    for (std::vector<glm::vec4> before; before != x1;) {
      before = x1;
      hold_bad_faces(s, b, x0, x1, met, o);
      apply_collision_constraints(s, b, x0, x1);
      hold_folding_motion(s, x0, x1);   // the sheets' order around a junction edge, faces turned over
      hold_star_crossings(s, x0, x1);   // faces that share only a vertex (the collisions skip them)
    }
    s.positions = x1;
    std::size_t moved = 0;
    for (std::size_t v = 0; v < x0.size(); ++v) moved += x1[v] != x0[v] ? 1 : 0;
    if (moved == 0) break;
    moves += moved;
  }
  return moves;
}

}  // namespace fracref
