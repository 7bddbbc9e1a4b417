// The walk of one S boundary edge across B along a plane (rim/exterior_mesh.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "rim/exterior_mesh.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

// Crossings of a B edge closer than this many plane tolerances to an end are that end.
constexpr double kVertexSnap = 1000.0;

struct Candidate {
  Location loc;
  std::uint32_t face = 0;
};

// Follows the curve where the plane meets B. Signs of B vertices against the plane are computed
// once and cached, so every triangle sees the same signs and the curve is one consistent polyline;
// near-zero distances are zero, so a curve grazing a vertex runs through it.
class Walker {
 public:
  Walker(const ExteriorMesh& m, const Location& p, const Location& q, const glm::dvec3& plane_normal, double tol,
         int branch = 0)
      : m_(m), p_(p), q_(q), normal_(plane_normal), tol_(tol), branch_(branch) {
    length_ = glm::length(q.point - p.point);
    direction_ = (q.point - p.point) / length_;
    if (p.kind == Location::kVertex) side_[p.id] = 0.0;
    if (q.kind == Location::kVertex) side_[q.id] = 0.0;
  }

  bool run(Trace& out, std::string& why) {
    out.from = p_;
    out.steps.clear();
    std::set<std::pair<int, std::uint32_t>> visited;
    mark(visited, p_);
    Location cur = p_;
    const std::size_t limit = m_.edges.size() + m_.positions.size() + 8;
    for (std::size_t step = 0; step < limit; ++step) {
      const std::vector<std::uint32_t> faces = location_faces(m_, cur);
      for (std::uint32_t f : faces)
        if (location_in_face(m_, q_, f)) {
          out.steps.push_back({q_, f});
          return true;
        }
      Candidate best;
      const double best_score = choose(cur, faces, visited, step == 0 ? branch_ : 0, best);
      if (best_score < -1.5) {
        why = "the walk found no way forward at " + format_point(cur.point) + " after " + std::to_string(step) + " steps";
        return false;
      }
      out.steps.push_back({best.loc, best.face});
      mark(visited, best.loc);
      cur = best.loc;
    }
    why = "the walk did not end";
    return false;
  }

 private:
  // The way forward from `cur`: of the exits of its faces not visited and in the corridor, ranked
  // by how straight they head for q (ties: the first found), the one of rank `rank` (0: the
  // straightest; 1: at p, the other way along the curve). Returns its score, -2 when none.
  double choose(const Location& cur, const std::vector<std::uint32_t>& faces,
                const std::set<std::pair<int, std::uint32_t>>& visited, int rank, Candidate& best) {
    std::vector<std::pair<double, Candidate>> ranked;
    std::set<std::pair<int, std::uint32_t>> seen;
    const glm::dvec3 toward = q_.point - cur.point;
    for (std::uint32_t f : faces) {
      candidates_.clear();
      exits(f, cur);
      for (const Candidate& c : candidates_) {
        if (visited.count(key(c.loc)) || closed_.count(key(c.loc)) || !in_corridor(c.loc.point)) continue;
        if (c.loc.kind != Location::kFace && !seen.insert(key(c.loc)).second) continue;
        const glm::dvec3 d = c.loc.point - cur.point;
        const double len = glm::length(d) * glm::length(toward);
        ranked.push_back({len > 0.0 ? glm::dot(d, toward) / len : -1.0, c});
      }
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    if (std::size_t(rank) >= ranked.size()) return -2.0;
    // Leaving p the other way: the ways not taken are closed, so the walk does not turn back
    // through p's triangle.
    if (rank > 0)
      for (std::size_t i = 0; i < ranked.size(); ++i)
        if (i != std::size_t(rank)) mark(closed_, ranked[i].second.loc);
    best = ranked[std::size_t(rank)].second;
    return ranked[std::size_t(rank)].first;
  }

  static std::pair<int, std::uint32_t> key(const Location& loc) { return {int(loc.kind), loc.id}; }
  static void mark(std::set<std::pair<int, std::uint32_t>>& visited, const Location& loc) {
    if (loc.kind != Location::kFace) visited.insert(key(loc));
  }

  double side(std::uint32_t v) {
    auto it = side_.find(v);
    if (it != side_.end()) return it->second;
    double s = glm::dot(normal_, m_.positions[v] - p_.point);
    if (std::abs(s) <= tol_) s = 0.0;
    side_.emplace(v, s);
    return s;
  }

  // Where the curve leaves triangle f from `cur`: its vertices on the plane and the crossings
  // of its sides whose ends lie strictly on opposite sides.
  void exits(std::uint32_t f, const Location& cur) {
    const auto& t = m_.triangles[f];
    const double s[3] = {side(t[0]), side(t[1]), side(t[2])};
    for (int k = 0; k < 3; ++k)
      if (s[k] == 0.0 && !(cur.kind == Location::kVertex && cur.id == t[k])) candidates_.push_back({vertex_location(m_, t[k]), f});
    for (int k = 0; k < 3; ++k) {
      const double a = s[k], b = s[(k + 1) % 3];
      if (!((a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0))) continue;
      const std::uint32_t e = m_.face_edges[f][k];
      if (cur.kind == Location::kEdge && cur.id == e) continue;
      const double sa = side(m_.edges[e].x), sb = side(m_.edges[e].y), at = sa / (sa - sb);
      // A crossing a hair from an end (the plane passes that close to a B vertex: a chord
      // through it, up to float rounding) is the vertex: its side is zero from now on, or the
      // curve would cross each edge around it there, one rim point per edge at one place.
      const double length = glm::length(m_.positions[m_.edges[e].y] - m_.positions[m_.edges[e].x]);
      if (std::min(at, 1.0 - at) * length <= kVertexSnap * tol_) {
        const std::uint32_t v = at < 0.5 ? m_.edges[e].x : m_.edges[e].y;
        side_[v] = 0.0;
        if (!(cur.kind == Location::kVertex && cur.id == v)) candidates_.push_back({vertex_location(m_, v), f});
        continue;
      }
      candidates_.push_back({edge_location(m_, e, at), f});
    }
  }

  // A trace is short next to B's curvature: it never goes far back behind p or past q.
  bool in_corridor(const glm::dvec3& x) const {
    const double along = glm::dot(x - p_.point, direction_);
    return along >= -length_ && along <= 2.0 * length_;
  }

  const ExteriorMesh& m_;
  Location p_, q_;
  glm::dvec3 normal_;
  double tol_;
  int branch_ = 0;
  double length_ = 0.0;
  glm::dvec3 direction_{0.0};
  std::map<std::uint32_t, double> side_;
  std::set<std::pair<int, std::uint32_t>> closed_;  // exits at p not taken (branch > 0)
  std::vector<Candidate> candidates_;
};

}  // namespace

Trace trace_on_exterior(const ExteriorMesh& m, const Location& p, const Location& q, double plane_tolerance,
                        const glm::dvec3& first_plane) {
  const glm::dvec3 d = q.point - p.point;
  const double length = glm::length(d);
  if (same_location(p, q) || length == 0.0) throw RunError("its ends lie on the same point of the exterior");
  const glm::dvec3 np = location_normal(m, p), nq = location_normal(m, q);
  std::vector<std::pair<glm::dvec3, double>> planes;  // (normal, the length it has for a plane at right angles)
  if (glm::length(first_plane) > 0.0) planes.emplace_back(first_plane, glm::length(first_plane));
  for (const glm::dvec3& n : {np + nq, np, nq}) planes.emplace_back(glm::cross(d, n), length * glm::length(n));
  std::string first_reason;
  for (const auto& [plane, scale] : planes) {
    const double len = glm::length(plane);
    if (!(len > 1e-9 * scale)) continue;  // edge along the normal: no plane
    Trace trace;
    std::string why;
    Walker walker(m, p, q, plane / len, plane_tolerance);
    if (walker.run(trace, why)) return trace;
    if (first_reason.empty()) first_reason = why;
  }
  if (first_reason.empty()) first_reason = "it is parallel to the exterior's normal";
  throw RunError(first_reason);
}

Trace trace_in_plane(const ExteriorMesh& m, const Location& p, const Location& q, double plane_tolerance,
                     const glm::dvec3& plane_normal, int branch) {
  const glm::dvec3 d = q.point - p.point;
  if (same_location(p, q) || glm::length(d) == 0.0) throw RunError("its ends lie on the same point of the exterior");
  const double len = glm::length(plane_normal);
  // The plane must hold the chord: its normal at right angles to it (up to rounding).
  if (!(len > 0.0) || std::abs(glm::dot(plane_normal, d)) > 1e-6 * len * glm::length(d))
    throw RunError("the plane does not hold it");
  Trace trace;
  std::string why;
  Walker walker(m, p, q, plane_normal / len, plane_tolerance, branch);
  if (!walker.run(trace, why)) throw RunError(why);
  return trace;
}

}  // namespace fracref::rim
