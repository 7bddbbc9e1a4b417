#include "refine/rim_smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geom/angles.hpp"
#include "geom/ccd.hpp"
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

struct RimEdge {
  std::uint32_t a = 0, b = 0;
  double lo_x = 0.0, hi_x = 0.0;
};

// Two rim edges that share no vertex and come within a quarter of the shorter one's length where
// they were farther apart: the moved ends of both.
void hold_rims_coming_together(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                               std::vector<std::uint32_t>& hold) {
  std::vector<RimEdge> rim;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeBoundary) continue;
    const glm::dvec3 p = point(x1, s.edges[e].x), q = point(x1, s.edges[e].y);
    const double pad = 0.25 * glm::distance(p, q);
    rim.push_back({s.edges[e].x, s.edges[e].y, std::min(p.x, q.x) - pad, std::max(p.x, q.x) + pad});
  }
  std::sort(rim.begin(), rim.end(), [](const RimEdge& u, const RimEdge& v) { return u.lo_x < v.lo_x; });
  const auto moved = [&](std::uint32_t v) { return x1[v] != x0[v]; };
  for (std::size_t i = 0; i < rim.size(); ++i)
    for (std::size_t j = i + 1; j < rim.size() && rim[j].lo_x <= rim[i].hi_x; ++j) {
      const RimEdge& e = rim[i];
      const RimEdge& f = rim[j];
      if (e.a == f.a || e.a == f.b || e.b == f.a || e.b == f.b) continue;
      if (!moved(e.a) && !moved(e.b) && !moved(f.a) && !moved(f.b)) continue;
      const double limit = 0.25 * std::min(glm::distance(point(x1, e.a), point(x1, e.b)), glm::distance(point(x1, f.a), point(x1, f.b)));
      const double gap1 = segment_distance(point(x1, e.a), point(x1, e.b), point(x1, f.a), point(x1, f.b));
      if (gap1 >= limit || gap1 >= segment_distance(point(x0, e.a), point(x0, e.b), point(x0, f.a), point(x0, f.b))) continue;
      for (const std::uint32_t v : {e.a, e.b, f.a, f.b})
        if (moved(v)) hold.push_back(v);
    }
}

// At a junction's end on B (three or more rim edges), two of its rim edges turned closer than
// kMinRimDegrees where they were wider: the end and the two far ends.
void hold_rims_closing_at_junctions(const std::vector<std::vector<std::uint32_t>>& nb, const std::vector<glm::vec4>& x0,
                                    const std::vector<glm::vec4>& x1, std::vector<std::uint32_t>& hold) {
  constexpr double kMinRimDegrees = 10.0;
  const double limit = glm::radians(kMinRimDegrees);
  for (std::uint32_t v = 0; v < nb.size(); ++v) {
    if (nb[v].size() < 3) continue;
    for (std::size_t i = 0; i < nb[v].size(); ++i)
      for (std::size_t k = i + 1; k < nb[v].size(); ++k) {
        const std::uint32_t a = nb[v][i], b = nb[v][k];
        if (x1[v] == x0[v] && x1[a] == x0[a] && x1[b] == x0[b]) continue;
        const double now = corner_angle(point(x1, v), point(x1, a), point(x1, b));
        if (now >= limit || now >= corner_angle(point(x0, v), point(x0, a), point(x0, b))) continue;
        for (const std::uint32_t w : {v, a, b})
          if (x1[w] != x0[w]) hold.push_back(w);
      }
  }
}

// Holds back moves that bring two sheets' rims together on B (above). The pieces stage cuts B
// along every rim: where two rims meet, the piece between them keeps no part of B (a thin
// piece's outline, as Cell Fracture's slivers make). Returns the vertices held.
std::size_t hold_rim_contacts(const FractureSurface& s, const std::vector<std::vector<std::uint32_t>>& nb,
                              const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) {
  std::vector<std::uint32_t> hold;
  hold_rims_coming_together(s, x0, x1, hold);
  hold_rims_closing_at_junctions(nb, x0, x1, hold);
  for (const std::uint32_t v : hold) x1[v] = x0[v];
  return hold.size();
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
      hold_rim_contacts(s, nb, x0, x1);  // two sheets' rims closing in on each other on B
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
