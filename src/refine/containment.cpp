#include "refine/containment.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "geom/face_guard.hpp"
#include "refine/collisions.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

// Threads deciding the tuck splits (the splits made do not depend on it).

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

// Points known to be inside B with their distance to it: the open ball of that radius around
// each misses B's surface, so every point in it is inside too (no inside test needed).
class InsideBalls {
 public:
  bool covers(const glm::dvec3& x) const {
    for (const auto& [c, r2] : balls_)
      if (glm::dot(x - c, x - c) < r2) return true;
    return false;
  }
  void add(const glm::dvec3& c, double squared_distance) { balls_.push_back({c, squared_distance * (1.0 - 1e-9)}); }

 private:
  std::vector<std::pair<glm::dvec3, double>> balls_;
};

// Whether x, at squared distance d from B, is outside B; inside points are remembered.
bool outside(const ExteriorSurface& b, const glm::dvec3& x, double d, InsideBalls& inside) {
  if (!b.contains(x)) return true;
  inside.add(x, d);
  return false;
}

// The sample of face f farthest outside B (a barycentric grid, corners excluded); false if none.
bool deepest_outside(const FractureSurface& s, std::uint32_t f, const ExteriorSurface& b, int grid, glm::vec3& weights) {
  const glm::uvec4 face = s.faces[f];
  double worst = 0.0;
  InsideBalls inside;
  for (int i = 0; i <= grid; ++i)
    for (int j = 0; i + j <= grid; ++j) {
      const int k = grid - i - j;
      if (std::max({i, j, k}) == grid) continue;
      const glm::dvec3 w(double(i) / grid, double(j) / grid, double(k) / grid);
      const glm::dvec3 x = w.x * at(s, face.x) + w.y * at(s, face.y) + w.z * at(s, face.z);
      if (inside.covers(x)) continue;
      const double d = b.squared_distance(x);
      if (d > worst && outside(b, x, d, inside)) worst = d, weights = glm::vec3(w);
    }
  return worst > 0.0;
}

double shortest_edge(const FractureSurface& s, const glm::uvec4& f) {
  return std::min({glm::distance(at(s, f.x), at(s, f.y)), glm::distance(at(s, f.y), at(s, f.z)),
                   glm::distance(at(s, f.z), at(s, f.x))});
}

double longest_edge(const FractureSurface& s, const glm::uvec4& f) {
  return std::max({glm::distance(at(s, f.x), at(s, f.y)), glm::distance(at(s, f.y), at(s, f.z)),
                   glm::distance(at(s, f.z), at(s, f.x))});
}

// The point of edge e farthest outside B, as t along it (samples off its ends, and off the
// rim strip at an end on B), and its squared distance to B; 0 if none is outside. `clearance`:
// the ends' distances to B where they are inside it (negative where unknown or not inside).
double deepest_outside_on_edge(const FractureSurface& s, std::uint32_t e, const ExteriorSurface& b, int grid, float& t,
                               glm::dvec2 clearance = glm::dvec2(-1.0)) {
  const glm::uvec2 ab = s.edges[e];
  const bool rim_a = s.vertex_flags[ab.x] & kVertexBoundary, rim_b = s.vertex_flags[ab.y] & kVertexBoundary;
  double worst = 0.0;
  InsideBalls inside;
  for (int k = 0; k < 2; ++k)
    if (clearance[k] > 0.0) inside.add(at(s, ab[k]), clearance[k] * clearance[k]);
  for (int i = 1; i < 2 * grid; ++i) {
    const double u = double(i) / (2 * grid);
    if ((rim_a && u < kRimShrink) || (rim_b && u > 1.0 - kRimShrink)) continue;
    const glm::dvec3 x = (1.0 - u) * at(s, ab.x) + u * at(s, ab.y);
    if (inside.covers(x)) continue;
    const double d = b.squared_distance(x);
    if (d > worst && outside(b, x, d, inside)) worst = d, t = float(u);
  }
  return worst;
}

// Splits gathered in one pass: each face at most once, each checked with a FaceGuard over S and
// the pass's earlier splits; made together by apply().
class SplitBatch {
 public:
  explicit SplitBatch(const FractureSurface& s) : s_(s), touched_(s.faces.size(), 0) {}
  // For splits whose new faces each lie inside one of `regions` (see FaceGuard's regions).
  SplitBatch(const FractureSurface& s, std::vector<Aabb> regions)
      : s_(s), touched_(s.faces.size(), 0), regions_(std::move(regions)) {}

  bool busy_edge(std::uint32_t e) const {
    for (std::uint32_t k = s_.ef_offsets[e]; k < s_.ef_offsets[e + 1]; ++k)
      if (touched_[s_.ef_faces[k]]) return true;
    return false;
  }
  bool busy_face(std::uint32_t f) const { return touched_[f] != 0; }

  // Edge e split at t, its vertex at q (already in the guard as vertex m): the new faces, and
  // the faces on e they replace, all at once (with q on e, each new face touches the faces on e
  // not yet replaced).
  struct EdgeEdit {
    std::uint32_t edge;
    float t;
    glm::dvec3 q;
    std::vector<TriangleIds> faces;
    std::vector<std::uint32_t> replaced;
    std::uint32_t hit = FaceGuard::kNoHit;  // the guard's first_snapshot_hit, when found ahead
    double reach = 0.0;                     // how far the new vertex is off e (see FaceGuard::clear)
  };
  EdgeEdit edge_edit(std::uint32_t e, float t, const glm::dvec3& q) {
    EdgeEdit edit{e, t, q, {}, {}, FaceGuard::kNoHit};
    const glm::uvec2 ab = s_.edges[e];
    const glm::dvec3 stored = stored_position(q);  // as the split will place it
    const std::uint32_t m = guard().add_vertex(stored);
    edit.reach = glm::distance(stored, (1.0 - double(t)) * at(s_, ab.x) + double(t) * at(s_, ab.y)) * (1.0 + 1e-6);
    for (std::uint32_t k = s_.ef_offsets[e]; k < s_.ef_offsets[e + 1]; ++k) {
      const glm::uvec4 f = s_.faces[s_.ef_faces[k]];
      const std::uint32_t z = f.x + f.y + f.z - ab.x - ab.y;
      edit.faces.push_back({ab.x, m, z});
      edit.faces.push_back({m, ab.y, z});
      edit.replaced.push_back(s_.ef_faces[k]);
    }
    return edit;
  }

  // Queues edge e split at t (its vertex at q) unless a face on e is taken or the new faces
  // would meet another face of S.
  bool add_edge(std::uint32_t e, float t, const glm::dvec3& q) {
    if (busy_edge(e)) return false;
    const EdgeEdit edit = edge_edit(e, t, q);
    if (!guard().clear(edit.faces, edit.replaced, edit.reach)) return false;
    accept(edit);
    return true;
  }

  // Edits prepared by edge_edit, their first hits on S found side by side on `threads` threads:
  // the exact tests against S are most of a chord pass.
  void find_hits(std::vector<EdgeEdit*>& edits, int threads) {
    if (edits.empty()) return;  // no guard to build (the last pass mostly finds no chord)
    const FaceGuard& g = guard();
    parallel_chunks(edits.size(), chunk_count(edits.size(), 8), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) edits[k]->hit = g.first_snapshot_hit(edits[k]->faces, edits[k]->replaced, edits[k]->reach);
    });
  }

  // add_edge for an edit whose first hit was found ahead: the same answer.
  bool add_prepared(const EdgeEdit& edit) {
    if (busy_edge(edit.edge) || !guard().clear_given(edit.faces, edit.replaced, edit.hit, edit.reach)) return false;
    accept(edit);
    return true;
  }

  void accept(const EdgeEdit& edit) {
    guard().accept(edit.faces, edit.replaced);
    for (std::uint32_t f : edit.replaced) touched_[f] = 1;
    requests_.push_back({SplitRequest::kEdge, edit.edge, glm::vec3(1.0f - edit.t, edit.t, 0.0f)});
    targets_.push_back(glm::vec3(edit.q));
  }

  // Queues face f split 1-to-3 at barycentric w (its vertex at q), unless taken or not clear.
  bool add_face(std::uint32_t f, const glm::vec3& w, const glm::dvec3& q) {
    if (busy_face(f)) return false;
    const glm::uvec4 face = s_.faces[f];
    const std::uint32_t m = guard().add_vertex(stored_position(q));
    const TriangleIds n1 = {face.x, face.y, m}, n2 = {face.y, face.z, m}, n3 = {face.z, face.x, m};
    if (!guard().clear({n1, n2, n3}, {f})) return false;
    guard().accept({n1, n2, n3}, {f});
    touched_[f] = 1;
    requests_.push_back({SplitRequest::kFace, f, w});
    targets_.push_back(glm::vec3(q));
    return true;
  }

  // Makes the queued splits; returns how many. See apply_splits for `deferred_origin`.
  std::size_t apply(FractureSurface& s, RefinementTree& tree, std::vector<std::uint32_t>* deferred_origin = nullptr) {
    if (!requests_.empty()) apply_splits(s, tree, requests_, &targets_, deferred_origin);
    return requests_.size();
  }

 private:
  FaceGuard& guard() {  // built on the first candidate: most passes split little
    if (guard_) return *guard_;
    if (regions_) guard_.emplace(double_positions(s_), face_triangles(s_), *regions_);
    else guard_.emplace(double_positions(s_), face_triangles(s_));
    return *guard_;
  }

  const FractureSurface& s_;
  std::vector<char> touched_;
  std::optional<FaceGuard> guard_;
  std::optional<std::vector<Aabb>> regions_;
  std::vector<SplitRequest> requests_;
  std::vector<glm::vec3> targets_;
};

glm::dvec3 inside_target(const ExteriorSurface& b, const glm::dvec3& x, double margin) {
  const ClosestPoint cp = closest_point(b.bvh, x);
  return stored_position(cp.point - margin * b.normal(cp.triangle));
}

// Distance to B is 1-Lipschitz: an edge between two inside vertices whose distances to B add up
// to more than its length stays inside B, and so does a face whose corners are all inside,
// farther from B than its longest edge; their samples need no queries. Per vertex: its distance
// to B when inside, -1 when outside or on the rim (every vertex's, computed up front on the
// threads: the passes below ask for nearly all of them).
class SurelyInside {
 public:
  SurelyInside(const FractureSurface& s, const ExteriorSurface& b) : s_(s), clearance_(s.positions.size()) {
    parallel_chunks(clearance_.size(), chunk_count(clearance_.size(), 64), default_threads(),
                    [&](std::size_t, std::size_t begin, std::size_t end) {
                      for (std::size_t v = begin; v < end; ++v) {
                        const glm::dvec3 x = at(s_, std::uint32_t(v));
                        clearance_[v] = (s_.vertex_flags[v] & kVertexBoundary) || !b.contains(x)
                                            ? -1.0
                                            : std::sqrt(b.squared_distance(x));
                      }
                    });
  }
  bool edge(std::uint32_t e) const {
    const glm::uvec2 ab = s_.edges[e];
    const double da = clearance(ab.x), db = clearance(ab.y);
    return da >= 0.0 && db >= 0.0 && da + db > glm::distance(at(s_, ab.x), at(s_, ab.y)) * (1.0 + 1e-9);
  }
  bool face(std::uint32_t f) const {
    const glm::uvec4 x = s_.faces[f];
    const double nearest = std::min({clearance(x.x), clearance(x.y), clearance(x.z)});
    return nearest >= 0.0 && nearest > longest_edge(s_, x) * (1.0 + 1e-9);
  }
  /// Distance from v to B when v is inside B and not on the rim, else -1.
  double clearance(std::uint32_t v) const { return clearance_[v]; }

 private:
  const FractureSurface& s_;
  std::vector<double> clearance_;
};

// find(k) for every k < n on the threads (each decided alone: the queries against B are most of
// a pass), the found splits in k order, so the batch below takes them as a serial loop would.
template <class T, class Find>
std::vector<T> found_in_order(std::size_t n, const Find& find) {
  const std::size_t chunks = chunk_count(n, 16);
  std::vector<std::vector<T>> parts(chunks);
  parallel_chunks(n, chunks, default_threads(), [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      if (std::optional<T> t = find(std::uint32_t(k))) parts[c].push_back(*t);
  });
  std::vector<T> out;
  for (auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

struct EdgeSplit {
  std::uint32_t element;  // the edge, or for a rim face the face
  std::uint32_t edge;
  float t;
  glm::dvec3 q;
};

// Splits of the interior edges that leave B; returns the number of splits.
std::size_t tuck_edges(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o) {
  const SurelyInside inside(s, b);
  const auto found = found_in_order<EdgeSplit>(s.edges.size(), [&](std::uint32_t e) -> std::optional<EdgeSplit> {
    float t = 0.0f;
    const glm::uvec2 ab = s.edges[e];
    if (s.edge_special[e] == kEdgeBoundary || inside.edge(e) ||
        deepest_outside_on_edge(s, e, b, o.sample_grid, t, {inside.clearance(ab.x), inside.clearance(ab.y)}) == 0.0)
      return std::nullopt;
    const double length = glm::distance(at(s, ab.x), at(s, ab.y));
    if (length <= 2.0 * o.min_edge * o.scale) return std::nullopt;
    const glm::dvec3 q = inside_target(b, (1.0 - t) * at(s, ab.x) + double(t) * at(s, ab.y),
                                       std::min(o.margin * o.scale, 0.1 * length));
    if (!b.contains(q)) return std::nullopt;
    return EdgeSplit{e, e, t, q};
  });
  SplitBatch batch(s);
  for (const EdgeSplit& c : found) batch.add_edge(c.edge, c.t, c.q);
  return batch.apply(s, tree);
}

// A rim face can meet B because its boundary edge's chord runs outside a concave B: the edge
// whose chord reaches farthest out is split there, the new vertex projected onto B (as the
// refiner's conforming splits do), which brings the chord toward B. A rim face that meets B
// with every chord inside has its longest boundary edge split at the midpoint: a finer rim
// follows B more closely. Returns the number of splits.
std::size_t tuck_rim_edges(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o) {
  const SurelyInside inside(s, b);
  const auto found = found_in_order<EdgeSplit>(s.faces.size(), [&](std::uint32_t f) -> std::optional<EdgeSplit> {
    if (inside.face(f) || !face_meets_exterior(s, f, b)) return std::nullopt;
    std::uint32_t edge = kNoEdge, longest = kNoEdge;
    double deepest = 0.0, longest_length = 0.0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = s.face_edges[3 * f + k];
      const double length = glm::distance(at(s, s.edges[e].x), at(s, s.edges[e].y));
      float t = 0.5f;
      if (s.edge_special[e] != kEdgeBoundary || length <= 2.0 * o.min_edge * o.scale) continue;
      if (length > longest_length) longest_length = length, longest = e;
      const double d = deepest_outside_on_edge(s, e, b, o.sample_grid, t);
      if (d > deepest) deepest = d, edge = e;
    }
    if (edge == kNoEdge) edge = longest;  // the face meets B off its chords: refine its rim
    if (edge == kNoEdge) return std::nullopt;
    const glm::uvec2 ab = s.edges[edge];
    return EdgeSplit{f, edge, 0.5f, b.closest_point(0.5 * (at(s, ab.x) + at(s, ab.y)))};
  });
  SplitBatch batch(s);
  for (const EdgeSplit& c : found)
    if (!batch.busy_face(c.element)) batch.add_edge(c.edge, c.t, c.q);
  return batch.apply(s, tree);
}

// Splits of the faces whose inside leaves B; returns the number of splits.
std::size_t tuck_faces(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o) {
  struct FaceSplit {
    std::uint32_t face;
    glm::vec3 w;
    glm::dvec3 q;
  };
  const SurelyInside inside(s, b);
  const auto found = found_in_order<FaceSplit>(s.faces.size(), [&](std::uint32_t f) -> std::optional<FaceSplit> {
    if (inside.face(f) || !face_meets_exterior(s, f, b)) return std::nullopt;
    glm::vec3 w(0.0f);
    if (!deepest_outside(s, f, b, o.sample_grid, w)) return std::nullopt;
    const glm::uvec4 face = s.faces[f];
    if (longest_edge(s, face) <= 2.0 * o.min_edge * o.scale) return std::nullopt;
    const glm::dvec3 x = double(w.x) * at(s, face.x) + double(w.y) * at(s, face.y) + double(w.z) * at(s, face.z);
    const glm::dvec3 q = inside_target(b, x, std::min(o.margin * o.scale, 0.2 * shortest_edge(s, face)));
    if (!b.contains(q)) return std::nullopt;
    return FaceSplit{f, w, q};
  });
  SplitBatch batch(s);
  for (const FaceSplit& c : found) batch.add_face(c.face, c.w, c.q);
  return batch.apply(s, tree);
}

}  // namespace

namespace {

// One pass of split_rim_chords; the chords' midpoints are inside B, so the new vertices are
// interior and between passes the edge table is all that must be rebuilt. The chords and their
// new vertices are found first, so that the FaceGuard indexes only the faces near them, a small
// part of S (a tree over all of S would be most of a pass).
std::size_t split_rim_chords_once(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o,
                                  std::vector<std::uint32_t>& origin) {
  struct Chord {
    std::uint32_t edge;
    glm::dvec3 mid, q;
    bool mid_inside, q_inside;
  };
  std::vector<Chord> chords;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const glm::uvec2 ab = s.edges[e];
    if (s.edge_special[e] != kEdgeBoundary && (s.vertex_flags[ab.x] & kVertexBoundary) &&
        (s.vertex_flags[ab.y] & kVertexBoundary))
      chords.push_back({e, 0.5 * (at(s, ab.x) + at(s, ab.y)), {}, false, false});
  }
  // Each chord's queries against B on its own, side by side (a serial loop was a tenth of a pass).
  std::vector<Aabb> regions(chords.size());
  auto place = [&](Chord& c, Aabb& region) {
    const glm::uvec2 ab = s.edges[c.edge];
    const double margin = std::min(o.margin * o.scale, 0.1 * glm::distance(at(s, ab.x), at(s, ab.y)));
    c.mid_inside = b.contains(c.mid);
    c.q = c.mid;
    if (!c.mid_inside || b.squared_distance(c.mid) < margin * margin) c.q = inside_target(b, c.mid, margin);
    c.q_inside = b.contains(c.q);
    // The new faces' corners: the faces' on the chord and the new vertex (rounded as stored).
    for (std::uint32_t k = s.ef_offsets[c.edge]; k < s.ef_offsets[c.edge + 1]; ++k)
      for (int i = 0; i < 3; ++i) region.expand(at(s, s.faces[s.ef_faces[k]][i]));
    region.expand(stored_position(c.q));
    region.expand(stored_position(c.mid));
  };
  parallel_chunks(chords.size(), chunk_count(chords.size(), 16), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k) place(chords[k], regions[k]);
                  });
  // Each chord's splits to try, in order: moved inward (the new faces bend and can cut a
  // neighbouring face at the rim), then at the midpoint itself. The first ones are tested against
  // S side by side, then all are offered in chord order as a serial loop would (a midpoint split
  // is tested when it is offered: most chords never need it).
  SplitBatch batch(s, std::move(regions));
  std::vector<std::optional<SplitBatch::EdgeEdit>> inward(chords.size());
  std::vector<SplitBatch::EdgeEdit*> ahead;
  for (std::size_t k = 0; k < chords.size(); ++k)
    if (chords[k].q_inside) ahead.push_back(&inward[k].emplace(batch.edge_edit(chords[k].edge, 0.5f, chords[k].q)));
  batch.find_hits(ahead, default_threads());
  for (std::size_t k = 0; k < chords.size(); ++k) {
    const Chord& c = chords[k];
    if (batch.busy_edge(c.edge)) continue;
    if (inward[k] && batch.add_prepared(*inward[k])) continue;
    if (c.q != c.mid && c.mid_inside) batch.add_edge(c.edge, 0.5f, c.mid);
  }
  return batch.apply(s, tree, &origin);
}

}  // namespace

std::size_t split_rim_chords(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o,
                             int passes) {
  const std::size_t first_vertex = s.positions.size(), first_face = s.faces.size();
  std::vector<std::uint32_t> origin;
  std::size_t total = 0;
  for (int pass = 0; pass < passes; ++pass) {
    const std::size_t made = split_rim_chords_once(s, tree, b, o, origin);
    total += made;
    if (made == 0) break;
  }
  if (total > 0) rebuild_after_splits(s, first_vertex, first_face, origin);
  return total;
}

bool face_meets_exterior(const FractureSurface& s, std::uint32_t f, const ExteriorSurface& b) {
  const glm::uvec4 face = s.faces[f];
  const glm::dvec3 c = (at(s, face.x) + at(s, face.y) + at(s, face.z)) / 3.0;
  glm::dvec3 x[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = at(s, face[k]);
    if (s.vertex_flags[face[k]] & kVertexBoundary) x[k] += kRimShrink * (c - x[k]);
  }
  return b.meets(x[0], x[1], x[2]) || !b.contains(c);
}

std::size_t tuck_inside(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& b, const TuckOptions& o) {
  std::size_t total = 0;
  for (int pass = 0; pass < o.passes; ++pass) {
    std::size_t made = tuck_edges(s, tree, b, o);
    if (made == 0) made = tuck_rim_edges(s, tree, b, o);
    if (made == 0) made = tuck_faces(s, tree, b, o);
    if (made == 0) break;
    total += made;
  }
  return total;
}

}  // namespace fracref
