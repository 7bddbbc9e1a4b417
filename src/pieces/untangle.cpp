// Traces that cross or touch, found exactly in each B triangle's barycentric plane, and their
// re-routing clear of the neighbouring traces they pass on the wrong side (pieces.hpp, 2b).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "geom/predicates.hpp"
#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {
namespace {

struct Segment {
  std::uint32_t trace = 0, step = 0;
  Location a, b;
};

Location step_start(const Trace& t, std::size_t i) { return i == 0 ? t.from : t.steps[i - 1].to; }

// Per B triangle, the segments lying in it; a segment along a B edge lies in both its triangles.
std::map<std::uint32_t, std::vector<Segment>> segments_by_face(const ExteriorMesh& m, const std::vector<EdgeTrace>& traces) {
  std::map<std::uint32_t, std::vector<Segment>> out;
  for (std::uint32_t i = 0; i < traces.size(); ++i)
    for (std::uint32_t j = 0; j < traces[i].trace.steps.size(); ++j) {
      const TraceStep& step = traces[i].trace.steps[j];
      const Segment seg{i, j, step_start(traces[i].trace, j), step.to};
      out[step.face].push_back(seg);
      const unsigned common = location_sides(m, seg.a, step.face) & location_sides(m, seg.b, step.face);
      if (common == 0) continue;
      const int k = (common & 1u) ? 0 : ((common & 2u) ? 1 : 2);
      for (std::uint32_t f : m.edge_faces[m.face_edges[step.face][k]])
        if (f != step.face) out[f].push_back(seg);
    }
  return out;
}

bool on_closed_segment(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& x) {
  return std::min(a.x, b.x) <= x.x && x.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= x.y && x.y <= std::max(a.y, b.y);
}

// Whether segments (a, b) and (c, d) of triangle f cross, touch or overlap beyond a shared end.
bool segments_conflict(const ExteriorMesh& m, std::uint32_t f, const Segment& s, const Segment& t) {
  const Location* p[4] = {&s.a, &s.b, &t.a, &t.b};
  glm::dvec2 uv[4];
  for (int i = 0; i < 4; ++i) {
    uv[i] = location_uv(m, *p[i], f);
    if (std::isnan(uv[i].x)) return false;
  }
  int shared = 0, si = 0, ti = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 2; j < 4; ++j)
      if (same_location(*p[i], *p[j])) ++shared, si = i, ti = j;
  if (shared >= 2) return true;
  if (shared == 1) {  // they meet at an end: a conflict only when they leave it in one direction
    const glm::dvec2 o = uv[si], x = uv[1 - si], y = uv[ti == 2 ? 3 : 2];
    return orient2d(o, x, y) == 0 && glm::dot(x - o, y - o) > 0.0;
  }
  const int o1 = orient2d(uv[0], uv[1], uv[2]), o2 = orient2d(uv[0], uv[1], uv[3]);
  const int o3 = orient2d(uv[2], uv[3], uv[0]), o4 = orient2d(uv[2], uv[3], uv[1]);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && on_closed_segment(uv[0], uv[1], uv[2])) || (o2 == 0 && on_closed_segment(uv[0], uv[1], uv[3])) ||
         (o3 == 0 && on_closed_segment(uv[2], uv[3], uv[0])) || (o4 == 0 && on_closed_segment(uv[2], uv[3], uv[1]));
}

// Where a point lies relative to a trace: how far, on which side and how far along.
struct Relation {
  double distance = 0.0;
  double lateral = 0.0;  // signed distance to the left of the trace (B's normal up)
  double along = 0.0;    // arc length of the nearest point of the trace
  bool beyond = false;   // nearest to an end of the trace: it does not pass the point
};

// A new route point of X: where it goes and how far along X it belongs.
struct Waypoint {
  double along;
  Location loc;
  std::uint32_t clear_of;
};

class Untangler {
 public:
  Untangler(const ExteriorMesh& m, std::vector<EdgeTrace>& traces, double plane_tolerance, double epsilon)
      : m_(m), traces_(traces), tolerance_(plane_tolerance), epsilon_(epsilon) {
    for (std::uint32_t i = 0; i < traces.size(); ++i) {
      incident_[traces[i].p].push_back(i);
      incident_[traces[i].q].push_back(i);
      if (traces[i].trace.from.kind == Location::kVertex) s_on_b_vertex_.insert(traces[i].trace.from.id);
      if (traces[i].trace.steps.back().to.kind == Location::kVertex) s_on_b_vertex_.insert(traces[i].trace.steps.back().to.id);
    }
  }

  std::uint32_t run() {
    std::uint32_t added = 0;
    for (std::size_t round = 0; round < kMaxRounds && added < kMaxRoutePoints; ++round) {
      const std::vector<TraceConflict> conflicts = find_trace_conflicts(m_, traces_);
      std::uint32_t fixed = 0;
      for (std::size_t c = 0; c < conflicts.size() && fixed == 0; ++c) fixed = resolve(conflicts[c]);
      if (fixed == 0) break;
      added += fixed;
    }
    return added;
  }

 private:
  static constexpr std::size_t kMaxRounds = 64;
  static constexpr std::uint32_t kMaxRoutePoints = 4096;
  static constexpr int kMaxTries = 3;        // re-routings of one trace clear of one other
  static constexpr double kReach = 0.1;      // neighbourhood of X, relative to its chord
  static constexpr double kOffset = 0.25;    // eps relative to the farthest neighbour
  static constexpr double kShortest = 0.1;   // eps at most, relative to the shortest chord
  static constexpr std::size_t kChainDepth = 3;
  static constexpr int kSamples = 16;        // per segment of the chain, for the side
  static constexpr double kMinSeparation = 1e-7;  // relative to B's diagonal: below, no side

  // A way to resolve a conflict: re-trace X through these route points.
  struct Plan {
    std::uint32_t x = 0, y = 0;
    double separation = 0.0;  // the farthest neighbour's distance from X: how sure the side is
    std::vector<Waypoint> waypoints;
  };

  double chord(std::uint32_t i) const { return glm::length(traces_[i].trace.steps.back().to.point - traces_[i].trace.from.point); }

  Relation relate(std::uint32_t x, const glm::dvec3& c) const {
    const Trace& t = traces_[x].trace;
    Relation best;
    best.distance = std::numeric_limits<double>::infinity();
    double start = 0.0;
    for (std::size_t j = 0; j < t.steps.size(); ++j) {
      const glm::dvec3 a = step_start(t, j).point, b = t.steps[j].to.point, d = b - a;
      const double len2 = glm::dot(d, d), len = std::sqrt(len2);
      const double u = len2 > 0.0 ? std::clamp(glm::dot(c - a, d) / len2, 0.0, 1.0) : 0.0;
      const glm::dvec3 near = a + u * d;
      const double dist = glm::length(c - near);
      if (dist < best.distance) {
        best.distance = dist;
        glm::dvec3 left = glm::cross(m_.face_normals[t.steps[j].face], d);
        const double ll = glm::length(left);
        best.lateral = ll > 0.0 ? glm::dot(left / ll, c - near) : 0.0;
        best.along = start + u * len;
        best.beyond = (j == 0 && u == 0.0) || (j + 1 == t.steps.size() && u == 1.0);
      }
      start += len;
    }
    return best;
  }

  // Y and the traces joined to it at S vertices near X (not X's own ends), a few links deep.
  std::vector<std::uint32_t> chain(std::uint32_t x, std::uint32_t y, double reach) const {
    std::vector<std::uint32_t> out{y};
    std::set<std::uint32_t> seen{x, y};
    for (std::size_t i = 0, depth_end = 1, depth = 0; i < out.size() && depth < kChainDepth; ++i) {
      for (std::uint32_t w : {traces_[out[i]].p, traces_[out[i]].q}) {
        if (w == traces_[x].p || w == traces_[x].q) continue;
        if (relate(x, end_point(out[i], w)).distance > reach) continue;
        for (std::uint32_t e : incident_.at(w))
          if (seen.insert(e).second) out.push_back(e);
      }
      if (i + 1 == depth_end) depth_end = out.size(), ++depth;
    }
    return out;
  }

  glm::dvec3 end_point(std::uint32_t i, std::uint32_t w) const {
    return traces_[i].p == w ? traces_[i].trace.from.point : traces_[i].trace.steps.back().to.point;
  }

  // Route points keeping X clear of the chain of Y, or none when the side is not clear.
  Plan plan(std::uint32_t x, std::uint32_t y) const {
    Plan out;
    out.x = x;
    out.y = y;
    if (tries_.count({x, y}) && tries_.at({x, y}) >= kMaxTries) return out;
    const double reach = kReach * chord(x);
    struct Near {
      Location loc;
      Relation rel;
      std::uint32_t trace;
    };
    std::vector<Near> near;
    double farthest = 0.0;
    int side = 0;
    for (std::uint32_t e : chain(x, y, reach)) {
      const Trace& t = traces_[e].trace;
      for (std::size_t j = 0; j <= t.steps.size(); ++j) {
        const Location& loc = j == 0 ? t.from : t.steps[j - 1].to;
        if (is_end_of(x, loc)) continue;
        const Relation rel = relate(x, loc.point);
        if (rel.distance <= reach && !rel.beyond) near.push_back({loc, rel, e});
      }
      // The side is judged on points all along the chain, those past X's ends included: the
      // chain is often farthest from X where it leaves it, around an end of X.
      for (std::size_t j = 0; j < t.steps.size(); ++j) {
        const glm::dvec3 a = step_start(t, j).point, b = t.steps[j].to.point;
        const int n = std::clamp(int(std::ceil(4.0 * glm::length(b - a) / reach)), 1, kSamples);
        for (int k = 0; k <= n; ++k) {
          const Relation rel = relate(x, a + (double(k) / n) * (b - a));
          if (rel.distance > reach || !(std::abs(rel.lateral) > farthest)) continue;
          farthest = std::abs(rel.lateral);
          side = rel.lateral > 0.0 ? 1 : -1;
        }
      }
    }
    if (side == 0 || farthest < kMinSeparation * m_.diagonal) return out;  // no side to judge by
    double shortest = chord(x);
    for (const Near& n : near)
      if (n.rel.lateral * side < kOffset * farthest) shortest = std::min(shortest, chord(n.trace));
    const double eps = std::min(kOffset * farthest, kShortest * shortest);
    out.separation = farthest;
    for (const Near& n : near) {
      if (n.rel.lateral * side >= eps) continue;
      glm::dvec3 left = glm::cross(location_normal(m_, n.loc), direction_at(x, n.rel.along));
      if (!(glm::length(left) > 0.0)) continue;
      left = glm::normalize(left);
      const Location route = locate_on_exterior(m_, n.loc.point - double(side) * eps * left, epsilon_, nullptr);
      if (route.kind == Location::kVertex && s_on_b_vertex_.count(route.id)) continue;  // an S vertex is there
      out.waypoints.push_back({n.rel.along, route, n.trace});
    }
    return out;
  }

  bool is_end_of(std::uint32_t x, const Location& loc) const {
    return same_location(loc, traces_[x].trace.from) || same_location(loc, traces_[x].trace.steps.back().to);
  }

  // The direction of trace x at arc length s.
  glm::dvec3 direction_at(std::uint32_t x, double s) const {
    const Trace& t = traces_[x].trace;
    glm::dvec3 d(0.0);
    for (std::size_t j = 0; j < t.steps.size(); ++j) {
      d = t.steps[j].to.point - step_start(t, j).point;
      s -= glm::length(d);
      if (s <= 0.0) break;
    }
    return d;
  }

  std::uint32_t resolve(const TraceConflict& c) {
    Plan plans[2] = {plan(c.trace_a, c.trace_b), plan(c.trace_b, c.trace_a)};
    if (plans[1].separation > plans[0].separation) std::swap(plans[0], plans[1]);
    for (Plan& p : plans) {
      if (p.waypoints.empty()) continue;
      ++tries_[{p.x, p.y}];
      if (retrace(p)) return std::uint32_t(p.waypoints.size());
    }
    return 0;
  }

  // X through its route points so far and the plan's, in order along X, leg by leg.
  bool retrace(Plan& p) {
    Trace& t = traces_[p.x].trace;
    double along = 0.0;
    for (std::size_t j = 0; j < t.steps.size(); ++j) {
      along += glm::length(t.steps[j].to.point - step_start(t, j).point);
      if (t.steps[j].clear_of != kNone && j + 1 < t.steps.size()) p.waypoints.push_back({along, t.steps[j].to, t.steps[j].clear_of});
    }
    std::stable_sort(p.waypoints.begin(), p.waypoints.end(), [](const Waypoint& a, const Waypoint& b) { return a.along < b.along; });
    std::vector<std::pair<Location, std::uint32_t>> points{{t.from, kNone}};
    for (const Waypoint& w : p.waypoints)
      if (!same_location(w.loc, points.back().first) && !same_location(w.loc, t.steps.back().to)) points.emplace_back(w.loc, w.clear_of);
    points.emplace_back(t.steps.back().to, kNone);
    Trace out;
    out.from = t.from;
    try {
      for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        Trace leg = trace_on_exterior(m_, points[i].first, points[i + 1].first, tolerance_);
        leg.steps.back().clear_of = points[i + 1].second;
        out.steps.insert(out.steps.end(), leg.steps.begin(), leg.steps.end());
      }
    } catch (const RunError&) {
      return false;
    }
    t = std::move(out);
    return true;
  }

  const ExteriorMesh& m_;
  std::vector<EdgeTrace>& traces_;
  double tolerance_, epsilon_;
  std::map<std::uint32_t, std::vector<std::uint32_t>> incident_;  // S vertex -> traces ending there
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> tries_;  // (X, Y) -> re-routings
  std::set<std::uint32_t> s_on_b_vertex_;                          // B vertices an S vertex lies on
};

}  // namespace

std::vector<TraceConflict> find_trace_conflicts(const ExteriorMesh& m, const std::vector<EdgeTrace>& traces) {
  std::vector<TraceConflict> out;
  for (const auto& [f, segs] : segments_by_face(m, traces))
    for (std::size_t i = 0; i < segs.size(); ++i)
      for (std::size_t j = i + 1; j < segs.size(); ++j) {
        const Segment &s = segs[i], &t = segs[j];
        if (s.trace == t.trace) continue;  // a walk never meets itself
        if (segments_conflict(m, f, s, t)) out.push_back({f, s.trace, s.step, t.trace, t.step});
      }
  return out;
}

std::uint32_t untangle_traces(const ExteriorMesh& m, std::vector<EdgeTrace>& traces, double plane_tolerance,
                              double location_epsilon) {
  return Untangler(m, traces, plane_tolerance, location_epsilon).run();
}

}  // namespace fracref::pieces_detail
