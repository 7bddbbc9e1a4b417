// The refiner's rim on B: the boundary edges conformed to B before the flow, each rim vertex's
// location on B (embedded, slid with refine.rim_motion, located after the splits), and the
// contact rule that keeps S's faces off B except at the rim.
#include <algorithm>
#include <cmath>
#include <map>

#include "refine/exterior_contact.hpp"
#include "refine/refiner.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref::refine_detail {

// The pieces stage traces every boundary edge of S across B; a long boundary edge whose chord
// cuts deep under a curved B traces a path far from its chord, and neighbouring traces can cross.
// Before the flow starts, boundary edges are split at their midpoint projected onto B until every
// chord is within kConformTolerance of B.
void Refiner::conform_boundary() {
  const double limit = kConformTolerance * o_.scale;
  for (int pass = 0; pass < kConformPasses; ++pass) {
    std::vector<SplitRequest> chosen;
    std::vector<glm::vec3> start, target;
    std::vector<char> touched(s_.faces.size(), 0);
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      if (touched[f]) continue;
      glm::uvec2 ab = s_.edges[e];
      glm::dvec3 mid = 0.5 * (glm::dvec3(glm::vec3(s_.positions[ab.x])) + glm::dvec3(glm::vec3(s_.positions[ab.y])));
      glm::dvec3 q = b_.closest_point(mid);
      if (glm::distance(q, mid) <= limit) continue;
      touched[f] = 1;
      chosen.push_back({SplitRequest::kEdge, e, glm::vec3(0.5f, 0.5f, 0.0f)});
      start.push_back(glm::vec3(mid));
      target.push_back(glm::vec3(q));
    }
    if (chosen.empty()) return;
    drop_colliding_insertions(chosen, start, target);
    if (chosen.empty()) return;
    apply_splits(s_, tree_, chosen, &target);
  }
}

// The faces the contact rule (refine/exterior_contact.hpp) flags at positions x, the rim where
// x puts it.
std::vector<std::uint32_t> Refiner::flagged_faces(const std::vector<glm::vec4>& x, const std::vector<float>& clearance) const {
  return o_.rim_motion ? faces_crossing_exterior(s_, x, mesh(), slid_rim(x), clearance)
                       : faces_crossing_exterior(s_, x, mesh(), rim_, clearance);
}

// The faces that meet B at x1 other than at their rim points (refine/exterior_contact.hpp) and
// have a corner that moved from x0.
std::vector<std::uint32_t> Refiner::new_crossings(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                                                  const std::vector<float>& clearance) const {
  std::vector<std::uint32_t> bad = flagged_faces(x1, clearance);
  // A face the rule flags at x0 already (it is conservative where a rim point lies on a concave
  // B edge: the face is inside B but not inside both planes) must not move either: the rule could
  // not tell when it goes through B. So every flagged face with a moved corner counts.
  std::vector<std::uint32_t> moved;
  for (std::uint32_t f : bad) {
    const glm::uvec4 t = s_.faces[f];
    if (x1[t.x] != x0[t.x] || x1[t.y] != x0[t.y] || x1[t.z] != x0[t.z]) moved.push_back(f);
  }
  return moved;
}

// S meets B only at its rim: the vertices of a face the step would take across B stay at x0,
// until no new crossing is left (with every vertex held, S is x0's).
std::size_t Refiner::hold_exterior_crossings(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                             const std::vector<float>& clearance) const {
  std::size_t held = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::uint32_t f : new_crossings(x0, x1, clearance))
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = s_.faces[f][k];
        if (x1[v] == x0[v]) continue;
        x1[v] = x0[v];
        ++held;
        changed = true;
      }
  }
  return held;
}

// S's rim is embedded in B once, after the conforming splits (fewer traces to walk), and S is
// trimmed to B there (rim/trim_to_exterior.hpp): from then on a rim edge is only split at a point
// of its own segment, in the same triangle of B, and the contact rule keeps S's faces off B.
void Refiner::embed_rim() {
  // With rim_motion the rim vertices keep the locations they slid to (rim::EmbedOptions::known).
  rim::EmbedOptions eo;
  if (o_.rim_motion && !rim_.on_b.empty()) eo.known = &rim_;
  rim::Embedding e = rim::embed_rim(s_, mesh(), eo);
  for (const rim::EmbeddedVertex& a : e.added) {
    tree_.parents.push_back(glm::uvec3(a.parents[0], a.parents[1], a.parents[2]));
    tree_.weights.push_back(glm::vec3(a.weights));
  }
  rim_ = std::move(e.rim);
}

// With rim_motion the flow slides rim vertices on B (apply_boundary_constraint projects them);
// each keeps a location: where it lands on B (its closest point). A weight below kSlideSnap is
// zeroed, so a vertex that slides a hair past a B edge stays on it: otherwise the rim edge to it
// would be split a hair from its end (reembed_rim), a near-duplicate vertex.
// \pre x of S's vertices, rim vertices on B.
rim::RimOnB Refiner::slid_rim(const std::vector<glm::vec4>& x) const {
  rim::RimOnB out = rim_;
  for (std::size_t v = 0; v < x.size() && v < out.on_b.size(); ++v) {
    if (!out.on_b[v] || glm::vec3(x[v]) == glm::vec3(out.at[v].point)) continue;
    double distance = 0.0;
    out.at[v] = rim::locate_on_exterior(mesh(), glm::dvec3(glm::vec3(x[v])), kSlideSnap, &distance);
  }
  return out;
}

// Rim vertices of x moved to their slid locations (slid_rim), so that S's positions, the contact
// rule and the pieces see the same rim.
void Refiner::snap_slid_rim(std::vector<glm::vec4>& x) const {
  const rim::RimOnB slid = slid_rim(x);
  for (std::size_t v = 0; v < x.size() && v < slid.on_b.size(); ++v)
    if (slid.on_b[v]) x[v] = glm::vec4(glm::vec3(slid.at[v].point), 1.0f);
}

// The rim vertices of rim edges that run along a B edge (both ends on it) past another rim point
// on that edge, with the rim at `rim`: the pieces stage cuts B along the rim and cannot order
// such a segment among the points on its edge. A slide makes one where the rim folds back along
// a B edge, two rim edges of one vertex snapped onto it.
std::vector<std::uint32_t> Refiner::rim_runs_past_rim_points(const rim::RimOnB& rim) const {
  const rim::ExteriorMesh& m = mesh();
  std::map<std::uint32_t, std::vector<std::pair<double, std::uint32_t>>> on_edge;  // B edge -> (t, rim vertex)
  for (std::uint32_t v = 0; v < rim.on_b.size(); ++v)
    if (rim.on_b[v] && rim.at[v].kind == rim::Location::kEdge) on_edge[rim.at[v].id].push_back({rim.at[v].t, v});
  // Where a location lies along B edge e (its t, 0 or 1 at e's ends), or -1 when not on e.
  auto along = [&](const rim::Location& l, std::uint32_t e) {
    if (l.kind == rim::Location::kEdge) return l.id == e ? l.t : -1.0;
    if (l.kind == rim::Location::kVertex) return l.id == m.edges[e].x ? 0.0 : (l.id == m.edges[e].y ? 1.0 : -1.0);
    return -1.0;
  };
  std::vector<std::uint32_t> out;
  for (std::uint32_t k = 0; k < s_.edges.size(); ++k) {
    if (s_.edge_special[k] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s_.edges[k];
    if (ab.x >= rim.on_b.size() || ab.y >= rim.on_b.size()) continue;
    // The B edge the segment may run along: one that an end lies inside (the other end on it too).
    const rim::Location &la = rim.at[ab.x], &lb = rim.at[ab.y];
    for (const rim::Location* end : {&la, &lb}) {
      if (end->kind != rim::Location::kEdge || (end == &lb && la.kind == rim::Location::kEdge && la.id == lb.id)) continue;
      const std::uint32_t e = end->id;
      const double ta = along(la, e), tb = along(lb, e);
      if (ta < 0.0 || tb < 0.0) continue;
      for (const auto& [t, v] : on_edge[e])
        if (v != ab.x && v != ab.y && t > std::min(ta, tb) && t < std::max(ta, tb)) out.insert(out.end(), {ab.x, ab.y, v});
    }
  }
  return out;
}

// The ends of rim edges that cross another rim edge inside a triangle of B, with the rim at
// `rim`: the pieces stage cuts the triangle along both and cannot ("two traced paths cross"). The
// same test as its cut: a proper crossing in the triangle's barycentric plane, exact (orient2d);
// edges sharing an end, and edges along a B edge (judged by rim_runs_past_rim_points), are not
// tested.
std::vector<std::uint32_t> Refiner::rim_segments_crossing(const rim::RimOnB& rim) const {
  const rim::ExteriorMesh& m = mesh();
  std::map<std::uint32_t, std::vector<glm::uvec2>> in_face;  // B triangle -> rim edges inside it
  for (std::uint32_t k = 0; k < s_.edges.size(); ++k) {
    if (s_.edge_special[k] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s_.edges[k];
    if (ab.x >= rim.on_b.size() || ab.y >= rim.on_b.size() || !rim.on_b[ab.x] || !rim.on_b[ab.y]) continue;
    const std::uint32_t f = rim::segment_face(m, rim.at[ab.x], rim.at[ab.y]);
    if (f != rim::kNone) in_face[f].push_back(ab);
  }
  std::vector<std::uint32_t> out;
  for (const auto& [f, edges] : in_face)
    for (std::size_t i = 0; i < edges.size(); ++i)
      for (std::size_t j = i + 1; j < edges.size(); ++j) {
        const glm::uvec2 e = edges[i], g = edges[j];
        if (e.x == g.x || e.x == g.y || e.y == g.x || e.y == g.y) continue;
        if (rim::segments_cross_in_face(m, f, rim.at[e.x], rim.at[e.y], rim.at[g.x], rim.at[g.y]))
          out.insert(out.end(), {e.x, e.y, g.x, g.y});
      }
  return out;
}

// The flow makes no two rim edges cross (the rim stays where it is, or with rim_motion
// hold_rim_degeneracies holds the slides that would), so a crossing the set-up's embedding left
// would only stop the pieces stage after the whole refinement, with an internal error: it is
// reported here, before the flow, naming where.
void Refiner::refuse_crossing_rim() const {
  const std::vector<std::uint32_t> crossing = rim_segments_crossing(rim_);
  if (crossing.empty()) return;
  const std::uint32_t a = crossing[0], b = crossing[1], c = crossing[2], d = crossing[3];
  const std::uint32_t f = rim::segment_face(mesh(), rim_.at[a], rim_.at[b]);
  throw RunError("the fracture surface's rim cannot be laid on the exterior: its edges " + std::to_string(a) + "-" +
                 std::to_string(b) + " and " + std::to_string(c) + "-" + std::to_string(d) + " cross inside exterior triangle " +
                 std::to_string(f) + " near " + rim::format_point(rim_.at[a].point) +
                 ", where two sheets meet the exterior closer together than its triangles are wide (a known limitation; "
                 "README, \"Some cuts fail on the default lattice\")");
}

// hold_coincident_rim, then each moved vertex of a rim edge that runs along a B edge past another
// rim point, or that crosses another rim edge inside a B triangle (and those points or edges'
// ends, when they moved) back at x0, until nothing more is held.
std::size_t Refiner::hold_rim_degeneracies(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) const {
  std::size_t held = 0;
  for (bool changed = true; changed;) {
    changed = false;
    held += hold_coincident_rim(s_, x0, x1);
    const rim::RimOnB rim = slid_rim(x1);  // once for both tests: it locates every moved rim vertex on B
    std::vector<std::uint32_t> bad = rim_runs_past_rim_points(rim);
    const std::vector<std::uint32_t> crossing = rim_segments_crossing(rim);
    bad.insert(bad.end(), crossing.begin(), crossing.end());
    for (const std::uint32_t v : bad)
      if (x1[v] != x0[v]) {
        x1[v] = x0[v];
        ++held;
        changed = true;
      }
  }
  return held;
}

// A rim vertex that slid into another triangle of B leaves its rim edges across B's edges: they
// are split where they cross them, as the rim was embedded at the start (embed_rim), before the
// iteration's splits, which split a rim edge only inside its triangle. The new vertices get what
// the refiner keeps per vertex (tree entry, last move, clearance, sample, velocity).
void Refiner::reembed_rim() {
  if (rim::find_unembedded_rim(s_, mesh(), rim_).empty()) return;
  embed_rim();
  inherit_moves();
  inherit_clearance(s_, tree_, clearance_);
  evaluate();
}

// Rim vertices made by splits since the last call lie on their rim edge's segment: their
// location is the point of that segment at the split's weight (the tree's), and their position
// that location's point.
void Refiner::locate_new_rim_vertices() {
  const std::size_t first = rim_.at.size();
  rim_.at.resize(s_.positions.size());
  rim_.on_b.resize(s_.positions.size(), 0);
  for (std::size_t v = first; v < s_.positions.size(); ++v) {
    if (!(s_.vertex_flags[v] & kVertexBoundary)) continue;
    const glm::uvec3 p = tree_.parents[v];
    const glm::vec3 w = tree_.weights[v];
    int ends[3], n = 0;
    for (int k = 0; k < 3; ++k)
      if (w[k] != 0.0f) ends[n++] = k;
    const int a = ends[0], b = n == 2 ? ends[1] : ends[0];
    if (n != 2 || !rim_.on_b[p[a]] || !rim_.on_b[p[b]])
      throw RunError("internal: rim vertex " + std::to_string(v) + " was split off a rim edge without a location on the exterior");
    const double t = double(w[b]) / (double(w[a]) + double(w[b]));
    rim_.at[v] = rim::split_location(mesh(), rim_, p[a], p[b], t);
    rim_.on_b[v] = 1;
    s_.positions[v] = glm::vec4(glm::vec3(rim_.at[v].point), 1.0f);
  }
}

}  // namespace fracref::refine_detail
