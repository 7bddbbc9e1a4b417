// embed_rim: locate, trace, split (rim/rim_on_b.hpp).
#include "rim/rim_on_b.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "geom/bvh.hpp"
#include "geom/face_guard.hpp"
#include "geom/predicates.hpp"
#include "io/polygon_triangulation.hpp"

#include "rim/trim_to_exterior.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

std::string pair_name(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

void add(TrimStats& to, const TrimStats& more) {
  to.cut_faces += more.cut_faces;
  to.removed_faces += more.removed_faces;
  to.new_vertices += more.new_vertices;
}

class Embedder {
 public:
  Embedder(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& o) : s_(s), m_(m), o_(o) {}

  Embedding run() {
    locate_rim();
    // Chords whose faces have a checked split are split first; the others are left to the trim,
    // which cuts S to B (a chord outside B, over a concave part of it, with its face), and what
    // it leaves of them, with the edges of the flaps it dropped, is split next: by checked splits,
    // with the flat splits the other way round and the bisections too, round after round
    // (split_checked). A face with no checked split left there
    // is split as a fan all the same, as the rim was embedded before (the trim and the pieces
    // then judge it): S is trimmed once more, and the flaps that drops split.
    split_unembedded(Fallback::kNone);
    out_.trim = trim_to_exterior(s_, m_, out_.rim, out_.added);
    if (split_checked() && split_unembedded(Fallback::kUnchecked).unchecked) {
      add(out_.trim, trim_to_exterior(s_, m_, out_.rim, out_.added));
      if (split_checked()) split_unembedded(Fallback::kUnchecked);
    }
    return std::move(out_);
  }

 private:
  // What a face with no checked split of its traces gets (split_unembedded): nothing, more
  // checked splits (choose_split's `more`), or an unchecked fan.
  enum class Fallback { kNone, kMore, kUnchecked };
  struct Pass {
    std::uint32_t split = 0;  // faces split
    bool unchecked = false;   // one of them as an unchecked fan
  };

  // Rounds of checked splits, more of them (Fallback::kMore), while a chord is left and a round
  // splits a face, at most kRounds: a bisection leaves two shorter chords to the next round.
  // Returns whether a chord is left.
  bool split_checked() {
    static constexpr int kRounds = 24;
    for (int round = 0; round < kRounds; ++round)
      if (find_unembedded_rim(s_, m_, out_.rim).empty() || split_unembedded(Fallback::kMore).split == 0) break;
    return !find_unembedded_rim(s_, m_, out_.rim).empty();
  }

  // Every rim edge whose ends share no triangle of B (a chord) split where its trace crosses B's
  // edges, one face of S at a time (choose_split), each face's new triangles checked against S as
  // it stands with the faces split before it, and against B. The new vertices are numbered by rim
  // edge, then the centroids by face. A face with no checked split is left as it is, or gets the
  // fallback: more checked splits (the other way round, a bisection), or an unchecked fan.
  Pass split_unembedded(Fallback fallback) {
    std::vector<std::pair<std::uint32_t, int>> order;  // (face, side) per untraced rim edge, in edge order
    std::map<std::uint32_t, std::array<bool, 3>> untraced;  // face -> its sides to trace
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      const std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      const int k = side_of(f, s_.edges[e]);
      if (common_face(m_, out_.rim.at[s_.faces[f][k]], out_.rim.at[s_.faces[f][(k + 1) % 3]]) != kNone) continue;
      untraced[f][std::size_t(k)] = true;
      order.push_back({f, k});
    }
    Pass pass;
    if (untraced.empty()) return pass;
    std::vector<glm::dvec3> x;
    std::vector<TriangleIds> faces;
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) x.push_back(point(v));
    for (const glm::uvec4& f : s_.faces) faces.push_back({f.x, f.y, f.z});
    FaceGuard guard(std::move(x), std::move(faces));
    std::map<std::uint32_t, Split> chosen;
    for (const auto& [f, sides] : untraced) {
      std::optional<Split> split = choose_split(f, sides, guard, fallback == Fallback::kMore);
      if (!split && fallback == Fallback::kUnchecked) split = fan_split(s_.faces[f], sides), pass.unchecked = true;
      if (split) pend_claims(*split), chosen.emplace(f, std::move(*split));
    }
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> ids;  // (face, side, point) -> S vertex
    for (const auto& [f, k] : order) {
      if (!chosen.count(f)) continue;
      const glm::uvec4 face = s_.faces[f];
      const TracedSide& side = chosen.at(f).sides[std::size_t(k)];
      for (std::uint32_t i = 0; i < side.points.size(); ++i)
        ids[{f, std::uint32_t(k), i}] = add_trace_vertex(side.points[i], side.along[i], face[k], face[(k + 1) % 3]);
    }
    for (const auto& [f, split] : chosen) commit(f, split, ids);
    rebuild_adjacency(s_);
    pass.split = std::uint32_t(chosen.size());
    return pass;
  }

  int side_of(std::uint32_t f, glm::uvec2 edge) const {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = s_.faces[f][k], b = s_.faces[f][(k + 1) % 3];
      if ((a == edge.x && b == edge.y) || (a == edge.y && b == edge.x)) return k;
    }
    throw RunError("internal: fracture surface face " + std::to_string(f) + " does not hold its edge " + pair_name(edge.x, edge.y));
  }

  void locate_rim() {
    out_.rim.at.assign(s_.positions.size(), Location{});
    out_.rim.on_b.assign(s_.positions.size(), 0);
    const double tolerance = o_.snap_tolerance * m_.diagonal;
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) {
      if (!(s_.vertex_flags[v] & kVertexBoundary)) continue;
      double distance = 0.0;
      const bool known = o_.known && v < o_.known->on_b.size() && o_.known->on_b[v];
      const Location loc = known ? o_.known->at[v] : locate_on_exterior(m_, at(s_, v), o_.location_epsilon, &distance);
      if (!(distance <= tolerance))
        throw RunError("fracture surface boundary vertex " + std::to_string(v) + " at " + format_point(at(s_, v)) + " is " +
                       std::to_string(distance) + " from the exterior (tolerance " + std::to_string(tolerance) +
                       "): the fracture surface must end on the exterior");
      if (loc.kind == Location::kVertex) claim(loc.id, v);
      out_.rim.at[v] = loc;
      out_.rim.on_b[v] = 1;
      s_.positions[v] = glm::vec4(glm::vec3(loc.point), 1.0f);
    }
  }

  void claim(std::uint32_t b, std::uint32_t v) {
    auto [it, inserted] = b_owner_.emplace(b, v);
    if (!inserted)
      throw RunError("fracture surface vertices " + std::to_string(it->second) + " and " + std::to_string(v) +
                     " both lie on exterior vertex " + std::to_string(b) + " at " + format_point(m_.positions[b]));
  }

  // The inner points of a rim edge's trace, each with its fraction of the trace's length (the
  // point of the chord it is recorded at).
  struct TracedSide {
    std::vector<Location> points;
    std::vector<double> along;
  };

  TracedSide traced_side(std::uint32_t p, std::uint32_t q, const Trace& trace) const {
    std::vector<double> length{0.0};
    glm::dvec3 last = out_.rim.at[p].point;
    for (const TraceStep& step : trace.steps) length.push_back(length.back() + glm::length(step.to.point - last)), last = step.to.point;
    TracedSide side;
    for (std::size_t i = 0; i + 1 < trace.steps.size(); ++i) {
      if (trace.steps[i].to.kind == Location::kFace)
        throw RunError("internal: the trace of fracture surface boundary edge " + pair_name(p, q) + " stopped inside a triangle");
      side.points.push_back(trace.steps[i].to);
      side.along.push_back(length.back() > 0.0 ? length[i + 1] / length.back() : 0.5);
    }
    return side;
  }

  // A face split along the traces of its rim sides: the polygon of its corners and the traces'
  // points, and the triangles that replace the face.
  struct Split {
    std::array<TracedSide, 3> sides;
    // Per polygon point: (-1, S id) for a corner of the face, (k, i) for point i of side k's
    // trace, (3, 0) for the face's centroid.
    std::vector<std::pair<int, std::uint32_t>> source;
    std::vector<glm::dvec3> points;
    std::vector<std::array<std::uint32_t, 3>> triangles;  // polygon point ids
  };

  void add_polygon(Split& split, const glm::uvec4& face) const {
    for (int k = 0; k < 3; ++k) {
      split.source.push_back({-1, face[k]});
      split.points.push_back(point(face[k]));
      const TracedSide& side = split.sides[std::size_t(k)];
      for (std::uint32_t i = 0; i < side.points.size(); ++i) {
        split.source.push_back({k, i});
        split.points.push_back(side.points[i].point);
      }
    }
  }

  // The traces across B at right angles to it (trace_on_exterior), the face a fan from the corner
  // opposite its one traced side, or from its centroid.
  Split fan_split(const glm::uvec4& face, const std::array<bool, 3>& untraced) const {
    Split split;
    int traced = 0, only = 0;
    for (int k = 0; k < 3; ++k) {
      if (!untraced[std::size_t(k)]) continue;
      const std::uint32_t p = face[k], q = face[(k + 1) % 3];
      Trace trace;
      try {
        trace = trace_on_exterior(m_, out_.rim.at[p], out_.rim.at[q], o_.plane_epsilon * m_.diagonal);
      } catch (const RunError& err) {
        throw RunError("fracture surface boundary edge " + pair_name(p, q) + " from " + format_point(at(s_, p)) + " to " +
                       format_point(at(s_, q)) + " cannot be traced on the exterior: " + err.what());
      }
      split.sides[std::size_t(k)] = traced_side(p, q, trace);
      if (!split.sides[std::size_t(k)].points.empty()) ++traced, only = k;
    }
    add_polygon(split, face);
    const std::uint32_t n = std::uint32_t(split.points.size());
    std::uint32_t apex = 0;
    while (!(split.source[apex].first == -1 && split.source[apex].second == face[(only + 2) % 3])) ++apex;
    if (traced > 1) {
      apex = n;
      split.source.push_back({3, 0});
      split.points.push_back(glm::dvec3(centroid(face)));
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = i, b = (i + 1) % n;
      if (a == apex || b == apex) continue;
      split.triangles.push_back({a, b, apex});
    }
    return split;
  }

  // The traces in the face's own plane (trace_in_plane), so the polygon is flat, triangulated in
  // that plane (triangulate_polygon); nothing when a walk in that plane does not reach its end.
  std::optional<Split> flat_split(const glm::uvec4& face, const std::array<bool, 3>& untraced, int branch = 0) const {
    const glm::dvec3 normal = face_normal(face);
    Split split;
    for (int k = 0; k < 3; ++k) {
      if (!untraced[std::size_t(k)]) continue;
      const std::uint32_t p = face[k], q = face[(k + 1) % 3];
      try {
        split.sides[std::size_t(k)] = traced_side(p, q, trace_in_plane(m_, out_.rim.at[p], out_.rim.at[q], o_.plane_epsilon * m_.diagonal, normal, branch));
      } catch (const RunError&) {
        return std::nullopt;
      }
    }
    add_polygon(split, face);
    std::vector<std::uint32_t> local(split.points.size());
    for (std::uint32_t i = 0; i < local.size(); ++i) local[i] = i;
    triangulate_polygon(split.points, local.data(), local.size(), split.triangles);
    return split;
  }

  // Whether a split keeps S embedded: every new triangle faces as the face did, is not a flap on
  // B, meets B only at its rim points (meets_exterior_off_rim) and no other face of S
  // (guard), and no trace passes a B vertex that already holds a rim vertex.
  bool acceptable(const Split& split, const glm::uvec4& face, std::uint32_t f, FaceGuard& guard,
                  std::vector<TriangleIds>& made) const {
    for (const TracedSide& side : split.sides)
      for (const Location& loc : side.points)
        if (loc.kind == Location::kVertex && (b_owner_.count(loc.id) || pending_.count(loc.id))) return false;
    const glm::dvec3 normal = face_normal(face);
    std::vector<std::uint32_t> guard_id(split.points.size());
    for (std::uint32_t i = 0; i < split.points.size(); ++i)
      guard_id[i] = split.source[i].first == -1 ? split.source[i].second : guard.add_vertex(split.points[i]);
    made.clear();
    for (const auto& t : split.triangles) {
      const glm::dvec3 a = split.points[t[0]], b = split.points[t[1]], c = split.points[t[2]];
      if (!(glm::dot(glm::cross(b - a, c - a), normal) > 0.0)) return false;
      std::array<const Location*, 3> rim{};
      bool all_on_b = true;
      for (int k = 0; k < 3; ++k) {
        rim[std::size_t(k)] = location_of(split, t[std::size_t(k)]);
        all_on_b = all_on_b && rim[std::size_t(k)];
      }
      if (all_on_b && closest_point(m_.bvh, (a + b + c) / 3.0).squared_distance <= std::pow(1e-9 * m_.diagonal, 2)) return false;
      if (meets_exterior_off_rim(m_, {a, b, c}, rim, false)) return false;
      made.push_back({guard_id[t[0]], guard_id[t[1]], guard_id[t[2]]});
    }
    return guard.clear(made, {f});
  }

  // Face f split along the traces of its untraced rim sides: the fan of the traces at right angles
  // to B (fan_split) where it keeps S embedded (acceptable), else the flat split in the face's
  // plane (flat_split) where that does; with `more`, else the flat split whose traces leave their
  // start the other way (round the other side of the face's section of B), else the bisection of
  // its first untraced side (bisect_split). The guard learns the split chosen; else nothing (a
  // side that cannot be traced at right angles to B leaves no fan).
  std::optional<Split> choose_split(std::uint32_t f, const std::array<bool, 3>& untraced, FaceGuard& guard,
                                    bool more) const {
    const glm::uvec4 face = s_.faces[f];
    std::optional<Split> fan;
    try {
      fan = fan_split(face, untraced);
    } catch (const RunError&) {  // a side that cannot be traced so: made unchecked, it throws again
    }
    if (checked(fan, face, f, guard)) return fan;
    std::optional<Split> flat = flat_split(face, untraced);
    if (checked(flat, face, f, guard)) return flat;
    if (!more) return std::nullopt;
    if (checked(flat = flat_split(face, untraced, 1), face, f, guard)) return flat;
    std::optional<Split> half = bisect_split(face, untraced);
    if (checked(half, face, f, guard)) return half;
    return std::nullopt;
  }

  // Whether there is a split and it is acceptable; then the guard learns it.
  bool checked(const std::optional<Split>& split, const glm::uvec4& face, std::uint32_t f, FaceGuard& guard) const {
    std::vector<TriangleIds> made;
    if (!split || !acceptable(*split, face, f, guard, made)) return false;
    guard.accept(made, {f});
    return true;
  }

  // The face's first untraced side p-q split at the point of B closest to the chord's midpoint
  // (recorded at the midpoint), the face a fan from its third corner r: (p, m, r), (m, q, r). Its
  // two halves are chords, or rim edges in one triangle of B, for the next round. Nothing when
  // that point is p's or q's location.
  std::optional<Split> bisect_split(const glm::uvec4& face, const std::array<bool, 3>& untraced) const {
    int k = 0;
    while (k < 3 && !untraced[std::size_t(k)]) ++k;
    if (k == 3) return std::nullopt;
    const std::uint32_t p = face[k], q = face[(k + 1) % 3];
    double distance = 0.0;
    const Location m = locate_on_exterior(m_, 0.5 * (point(p) + point(q)), o_.location_epsilon, &distance);
    if (same_location(m, out_.rim.at[p]) || same_location(m, out_.rim.at[q])) return std::nullopt;
    Split split;
    split.sides[std::size_t(k)].points.push_back(m);
    split.sides[std::size_t(k)].along.push_back(0.5);
    add_polygon(split, face);
    // polygon: corners in order with m after corner k; r is the corner before k (cyclically)
    const std::uint32_t n = std::uint32_t(split.points.size());  // 4
    std::uint32_t r = 0;
    while (!(split.source[r].first == -1 && split.source[r].second == face[(k + 2) % 3])) ++r;
    for (std::uint32_t i = 0; i < n; ++i)
      if (i != r && (i + 1) % n != r) split.triangles.push_back({i, (i + 1) % n, r});
    return split;
  }

  void pend_claims(const Split& split) {
    for (const TracedSide& side : split.sides)
      for (const Location& loc : side.points)
        if (loc.kind == Location::kVertex) pending_.insert(loc.id);
  }

  // The location of a polygon point on B, or null.
  const Location* location_of(const Split& split, std::uint32_t i) const {
    const auto [k, id] = split.source[i];
    if (k == 3) return nullptr;
    if (k >= 0) return &split.sides[std::size_t(k)].points[id];
    return out_.rim.on_b[id] ? &out_.rim.at[id] : nullptr;
  }

  // A traced point of rim edge p-q as a new vertex of S, recorded on the chord at its fraction
  // `t` of the trace's length.
  std::uint32_t add_trace_vertex(const Location& loc, double t, std::uint32_t p, std::uint32_t q) {
    const std::uint32_t v = std::uint32_t(s_.positions.size());
    if (loc.kind == Location::kVertex) claim(loc.id, v);
    s_.positions.push_back(glm::vec4(glm::vec3(loc.point), 1.0f));
    out_.rim.at.push_back(loc);
    out_.rim.on_b.push_back(1);
    out_.added.push_back({v, {p, q, q}, glm::dvec3(1.0 - t, t, 0.0)});
    return v;
  }

  // The split made: its triangles become f and new faces of f's pieces, over the traced points'
  // vertices (`ids`) and, for a fan from the centroid, a new vertex there.
  void commit(std::uint32_t f, const Split& split, const std::map<std::array<std::uint32_t, 3>, std::uint32_t>& ids) {
    const glm::uvec4 face = s_.faces[f];
    std::vector<std::uint32_t> local;
    for (const auto& [k, i] : split.source) {
      if (k == -1) {
        local.push_back(i);
      } else if (k == 3) {
        const std::uint32_t v = std::uint32_t(s_.positions.size());
        s_.positions.push_back(glm::vec4(centroid(face), 1.0f));
        out_.rim.at.push_back(Location{});
        out_.rim.on_b.push_back(0);
        out_.added.push_back({v, {face.x, face.y, face.z}, glm::dvec3(1.0 / 3.0)});
        local.push_back(v);
      } else {
        local.push_back(ids.at({f, std::uint32_t(k), i}));
      }
    }
    for (std::size_t i = 0; i < split.triangles.size(); ++i) {
      const auto& t = split.triangles[i];
      const glm::uvec4 tri(local[t[0]], local[t[1]], local[t[2]], 0u);
      if (i == 0) s_.faces[f] = tri;
      else s_.faces.push_back(tri), s_.face_pieces.push_back(s_.face_pieces[f]);
    }
  }

  glm::vec3 centroid(const glm::uvec4& face) const {
    return (glm::vec3(s_.positions[face.x]) + glm::vec3(s_.positions[face.y]) + glm::vec3(s_.positions[face.z])) / 3.0f;
  }
  glm::dvec3 face_normal(const glm::uvec4& face) const {
    return glm::cross(point(face.y) - point(face.x), point(face.z) - point(face.x));
  }
  // Where a vertex lies: a rim vertex at its location, any other at its position.
  glm::dvec3 point(std::uint32_t v) const { return v < out_.rim.on_b.size() && out_.rim.on_b[v] ? out_.rim.at[v].point : at(s_, v); }

  FractureSurface& s_;
  const ExteriorMesh& m_;
  EmbedOptions o_;
  Embedding out_;
  std::map<std::uint32_t, std::uint32_t> b_owner_;  // B vertex -> the S vertex on it
  std::set<std::uint32_t> pending_;  // B vertices the traces of the splits chosen so far pass
};

}  // namespace

Embedding embed_rim(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& options) {
  return Embedder(s, m, options).run();
}

Location split_location(const ExteriorMesh& m, const RimOnB& rim, std::uint32_t a, std::uint32_t b, double t) {
  return location_between(m, rim.at[a], rim.at[b], t);
}

std::string find_unembedded_rim(const FractureSurface& s, const ExteriorMesh& m, const RimOnB& rim) {
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s.edges[e];
    for (std::uint32_t v : {ab.x, ab.y})
      if (v >= rim.on_b.size() || !rim.on_b[v]) return "fracture surface rim vertex " + std::to_string(v) + " has no location on the exterior";
    if (common_face(m, rim.at[ab.x], rim.at[ab.y]) == kNone)
      return "fracture surface rim edge " + pair_name(ab.x, ab.y) + " does not lie in one triangle of the exterior";
  }
  return "";
}

}  // namespace fracref::rim
