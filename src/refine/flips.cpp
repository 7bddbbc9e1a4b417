#include "refine/flips.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "geom/bvh.hpp"
#include "geom/bvh_traverse.hpp"
#include "geom/intersect.hpp"
#include "geom/quad_prism.hpp"
#include "util/key_set.hpp"
#include "util/parallel.hpp"

#include "refine/topology_edit.hpp"

namespace fracref {

namespace {

// Leaves of 8, as the CCD's trees: the check after the pass is mostly box traversal (half the
// faces of the bunny's final surface against all of them, 4.9M overlapping pairs: 170 -> 155 ms).
constexpr std::uint32_t kFlipTreeLeaf = 8;

struct Quad {
  glm::dvec3 a, b, c, d;  // faces (a, b, c), (b, a, d) -> (c, a, d), (d, b, c)
  double pa, pb, pc, pd;
};

double tri_energy(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double pa, double pb, double pc) {
  return 0.5 * glm::length(glm::cross(b - a, c - a)) * (pa + pb + pc) / 3.0;
}

glm::dvec3 unit_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 n = glm::cross(b - a, c - a);
  double l = glm::length(n);
  return l > 0.0 ? n / l : glm::dvec3(0.0);
}

// The cosine of the smallest angle of triangle (a, b, c) (1 for a degenerate one): angles compare
// as their cosines do, reversed, without an acos per corner.
double max_cosine(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  auto cosine = [](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    const glm::dvec3 u = q - p, v = r - p;
    const double lu = glm::length(u), lv = glm::length(v);
    if (lu == 0.0 || lv == 0.0) return 1.0;
    return std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0);
  };
  return std::max({cosine(a, b, c), cosine(b, c, a), cosine(c, a, b)});
}

bool flip_improves(const Quad& q, const FlipOptions& o) {
  const double cos_min = std::cos(o.min_angle * M_PI / 180.0);
  const double before = std::max(max_cosine(q.a, q.b, q.c), max_cosine(q.b, q.a, q.d));
  if (before <= cos_min) return false;
  const double after = std::max(max_cosine(q.c, q.a, q.d), max_cosine(q.d, q.b, q.c));
  if (after >= before) return false;
  glm::dvec3 n1 = unit_normal(q.a, q.b, q.c), n2 = unit_normal(q.b, q.a, q.d);
  if (glm::dot(n1, n2) < std::cos(o.max_dihedral * M_PI / 180.0)) return false;
  glm::dvec3 m1 = unit_normal(q.c, q.a, q.d), m2 = unit_normal(q.d, q.b, q.c);
  glm::dvec3 avg = n1 + n2;
  if (glm::dot(m1, avg) <= 0.0 || glm::dot(m2, avg) <= 0.0) return false;
  double e_old = tri_energy(q.a, q.b, q.c, q.pa, q.pb, q.pc) + tri_energy(q.b, q.a, q.d, q.pb, q.pa, q.pd);
  double e_new = tri_energy(q.c, q.a, q.d, q.pc, q.pa, q.pd) + tri_energy(q.d, q.b, q.c, q.pd, q.pb, q.pc);
  return e_new <= e_old;
}

// A flip changes which face of the quad lies on each of its four outer edges; at a junction
// (non-manifold) edge that turns the face around the edge to a new opposite vertex and can fold it
// past another piece's face, so quads touching a junction are left alone. Both ends of a junction
// edge are flagged non-manifold: only such edges are looked up.
bool touches_junction(const FractureSurface& s, glm::uvec2 ab, glm::uvec2 cd) {
  auto junction_vertex = [&](std::uint32_t v) { return (s.vertex_flags[v] & kVertexNonManifold) != 0; };
  for (std::uint32_t p : {ab.x, ab.y})
    for (std::uint32_t q : {cd.x, cd.y}) {
      if (!junction_vertex(p) || !junction_vertex(q)) continue;
      std::uint32_t e = find_edge(s, p, q);
      if (e != kNoEdge && s.edge_special[e] == kEdgeNonManifold) return true;
    }
  return false;
}

// A flip that passes every test that does not depend on the pass's earlier flips.
struct FlipCandidate {
  std::uint32_t edge;
  glm::uvec2 opposite, faces;
};

// Candidates in edge order. Judged on S as the pass found it: a face flipped earlier in the pass
// is `used` and skipped later, and flip_edge leaves the other faces and the (stale) adjacency as
// they were, so each test below gives the answer it would give at its turn.
std::vector<FlipCandidate> candidate_flips(const FractureSurface& s, std::span<const glm::vec4> samples, const FlipOptions& o) {
  auto x = [&](std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); };
  const double cos_min = std::cos(o.min_angle * M_PI / 180.0);
  // Only edges of a slim face are candidates: judged once per face, before the costlier tests.
  std::vector<char> slim(s.faces.size(), 0);
  parallel_chunks(s.faces.size(), chunk_count(s.faces.size(), 4096), o.threads,
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t f = begin; f < end; ++f)
                      slim[f] = max_cosine(x(s.faces[f].x), x(s.faces[f].y), x(s.faces[f].z)) > cos_min;
                  });
  const std::size_t chunks = chunk_count(s.edges.size(), 4096);
  std::vector<std::vector<FlipCandidate>> parts(chunks);
  parallel_chunks(s.edges.size(), chunks, o.threads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (auto e = std::uint32_t(begin); e < end; ++e) {
      glm::uvec2 cd, ff;
      if (s.edge_special[e] != kEdgeRegular) continue;
      const std::uint32_t f1 = s.ef_faces[s.ef_offsets[e]], f2 = s.ef_faces[s.ef_offsets[e] + 1];
      if (!(slim[f1] || slim[f2]) || !flip_candidates(s, e, cd, ff)) continue;
      const glm::uvec2 ab = s.edges[e];
      const Quad q{x(ab.x), x(ab.y), x(cd.x), x(cd.y), samples[ab.x].x, samples[ab.y].x, samples[cd.x].x, samples[cd.y].x};
      if (flip_improves(q, o) && !touches_junction(s, ab, cd)) parts[c].push_back({e, cd, ff});
    }
  });
  std::vector<FlipCandidate> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

// The pairs (i, j) of faces that meet (exact, as mesh_faces_intersect), i from `query` and j any
// face of S other than i; in order.
std::vector<std::pair<std::uint32_t, std::uint32_t>> meeting_faces(const std::vector<glm::dvec3>& x,
                                                                   const std::vector<TriangleIds>& faces,
                                                                   const std::vector<std::uint32_t>& query,
                                                                   const Bvh& all, int threads) {
  std::vector<TriangleIds> picked;
  for (std::uint32_t f : query) picked.push_back(faces[f]);
  BvhOptions o;
  o.leaf_size = kFlipTreeLeaf;
  o.threads = threads;
  const Bvh tree = build_bvh(triangle_boxes(x, picked, threads), o);
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  auto out = collect_overlaps<Pair>(tree, all, false, threads, [&](std::uint32_t k, std::uint32_t j, std::vector<Pair>& found) {
    if (query[k] != j && mesh_faces_intersect(x, faces[query[k]], faces[j])) found.emplace_back(query[k], j);
  });
  std::sort(out.begin(), out.end());
  return out;
}

// Each flip's new faces lie in the tetrahedron of its quad: a face that its QuadPrism separates
// from the quad meets neither of them, and needs no exact test (most of the pairs met in the
// check below: a twentieth of the wall's instructions, though little of its time, which goes to
// the traversal).
class FlipPrisms {
 public:
  // `quads`: per flip, its corners in order around the quad; `owner`: face -> flip or -1.
  FlipPrisms(const std::vector<glm::dvec3>& x, std::vector<std::array<std::uint32_t, 4>> quads,
             const std::vector<std::int32_t>& owner, int threads)
      : x_(x), quads_(std::move(quads)), owner_(owner), prisms_(quads_.size()) {
    parallel_chunks(quads_.size(), chunk_count(quads_.size(), 1024), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        const auto& q = quads_[k];
        const std::array<glm::dvec3, 4> p = {x[q[0]], x[q[1]], x[q[2]], x[q[3]]};
        const glm::dvec3 n = glm::cross(p[2] - p[0], p[3] - p[1]);
        if (glm::length(n) > 0.0) prisms_[k].emplace(p, n);
      }
    });
  }
  // Whether face f's flip (if any) has a prism that separates face g from its quad.
  bool separated(std::uint32_t f, const TriangleIds& g) const {
    const std::int32_t k = owner_[f];
    if (k < 0 || !prisms_[std::size_t(k)]) return false;
    const auto& q = quads_[std::size_t(k)];
    std::array<int, 3> shared{-1, -1, -1};
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 4; ++c)
        if (g[i] == q[c]) shared[i] = c;
    return prisms_[std::size_t(k)]->separates({x_[g[0]], x_[g[1]], x_[g[2]]}, shared);
  }

 private:
  const std::vector<glm::dvec3>& x_;
  std::vector<std::array<std::uint32_t, 4>> quads_;
  const std::vector<std::int32_t>& owner_;
  std::vector<std::optional<QuadPrism>> prisms_;
};

// The pairs (i, j), i < j, of faces of S that meet (exact, as mesh_faces_intersect), one of them
// marked; in order. One tree over the marked faces, met with itself, and one over the others, met
// with the first: one tree over all faces met with itself also walked the pairs of two unmarked
// faces (a third of the bunny's 4.3M overlapping pairs), and a tree over the marked faces met
// with one over all of them cost a build more and met each pair of two marked faces twice.
std::vector<std::pair<std::uint32_t, std::uint32_t>> meeting_marked_faces(const std::vector<glm::dvec3>& x,
                                                                          const std::vector<TriangleIds>& faces,
                                                                          const std::vector<char>& marked,
                                                                          const FlipPrisms& prisms, int threads) {
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  std::vector<std::uint32_t> ids[2];  // [0]: unmarked faces, [1]: marked ones, in face order
  for (std::uint32_t f = 0; f < faces.size(); ++f) ids[marked[f] != 0].push_back(f);
  Bvh trees[2];
  parallel_chunks(2, 2, threads, [&](std::size_t k, std::size_t, std::size_t) {
    std::vector<TriangleIds> picked(ids[k].size());
    for (std::size_t i = 0; i < picked.size(); ++i) picked[i] = faces[ids[k][i]];
    BvhOptions o;
    o.leaf_size = kFlipTreeLeaf;
    trees[k] = build_bvh(triangle_boxes(x, picked), o);
  });
  auto pairs = [&](bool self, int other) {
    return collect_overlaps<Pair>(trees[1], trees[other], self, threads,
                                  [&](std::uint32_t i, std::uint32_t j, std::vector<Pair>& found) {
                                    const std::uint32_t f = ids[1][i], g = ids[other][j];
                                    if (prisms.separated(f, faces[g]) || (other == 1 && prisms.separated(g, faces[f])))
                                      return;
                                    if (mesh_faces_intersect(x, faces[f], faces[g]))
                                      found.emplace_back(std::min(f, g), std::max(f, g));
                                  });
  };
  std::vector<Pair> out = pairs(true, 1);
  const std::vector<Pair> rest = pairs(false, 0);
  out.insert(out.end(), rest.begin(), rest.end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::size_t flip_slim_triangles(FractureSurface& s, std::span<const glm::vec4> samples, const ExteriorSurface&,
                                const FlipOptions& o) {
  const std::vector<FlipCandidate> candidates = candidate_flips(s, samples, o);
  if (candidates.empty()) return 0;
  // The flips are made first (in edge order, each face at most once) and checked afterwards: a
  // flip moves surface inside its quad when the quad is not flat, which can cut through a nearby
  // sheet of S. One pass of the new faces against all of S finds that; the later of two flips
  // whose faces meet, and a flip whose faces meet any other face, is undone, and the faces it
  // restores are checked in turn (they were S's, so they can meet only faces of flips still made).
  // Checking each candidate's quad before its flip tested ~60 faces against both new faces for
  // each of ~30K candidates and refused none on the bunny: a quarter of its refinement time.
  struct Made {
    std::uint32_t faces[2];
    glm::uvec4 old[2];
  };
  std::vector<Made> made;
  std::vector<std::int32_t> owner(s.faces.size(), -1);  // face -> index in `made` while flipped
  std::vector<char> used(s.faces.size(), 0);
  // Edges this pass made (the adjacency is stale), as (smaller id << 32 | larger id): a hash set,
  // as only membership is asked (an ordered set of pairs took a tenth of the pass's serial time).
  KeySet created(candidates.size());  // keys are never 0: a diagonal joins two distinct vertices
  for (const FlipCandidate& c : candidates) {
    const auto [lo, hi] = std::minmax(c.opposite.x, c.opposite.y);
    const std::uint64_t diagonal = (std::uint64_t(lo) << 32) | hi;
    if (used[c.faces.x] || used[c.faces.y] || created.contains(diagonal)) continue;
    const Made m{{c.faces.x, c.faces.y}, {s.faces[c.faces.x], s.faces[c.faces.y]}};
    // Neither face has changed since the candidate was found, nor has the (stale) edge table, so
    // flip_edge would find this very quad again: the flip is made from it directly.
    const glm::uvec2 e = s.edges[c.edge];
    s.faces[c.faces.x] = glm::uvec4(c.opposite.x, e.x, c.opposite.y, 0u);
    s.faces[c.faces.y] = glm::uvec4(c.opposite.y, e.y, c.opposite.x, 0u);
    created.insert(diagonal);
    used[c.faces.x] = used[c.faces.y] = 1;
    owner[c.faces.x] = owner[c.faces.y] = std::int32_t(made.size());
    made.push_back(m);
  }
  if (made.empty()) return 0;
  const std::vector<glm::dvec3> x = double_positions(s);
  std::vector<TriangleIds> faces = face_triangles(s);
  std::vector<char> flipped(faces.size(), 0);
  std::vector<std::array<std::uint32_t, 4>> quads;  // new faces (c, a, d), (d, b, c): c, a, d, b
  for (const Made& m : made) {
    flipped[m.faces[0]] = flipped[m.faces[1]] = 1;
    const TriangleIds &n0 = faces[m.faces[0]], &n1 = faces[m.faces[1]];
    quads.push_back({n0[0], n0[1], n0[2], n1[1]});
  }
  const FlipPrisms prisms(x, std::move(quads), owner, o.threads);
  std::vector<std::uint32_t> check;
  std::size_t undone = 0;
  // Over the faces as they are after the first undos, built only when there are any. A face
  // restored by a later undo keeps its flipped box here, so only pairs of two restored faces
  // could be missed, and those were both S's: they cannot meet.
  Bvh all;
  for (bool first = true; first || !check.empty(); first = false) {
    std::set<std::int32_t> undo;
    if (!first && all.nodes.empty()) {
      BvhOptions tree_options;
      tree_options.threads = o.threads;
      tree_options.leaf_size = kFlipTreeLeaf;
      all = build_bvh(triangle_boxes(x, faces, o.threads), tree_options);
    }
    const auto meeting = first ? meeting_marked_faces(x, faces, flipped, prisms, o.threads)
                               : meeting_faces(x, faces, check, all, o.threads);
    for (const auto& [f, g] : meeting) {
      // A flip's faces meeting S's: that flip goes; two flips' faces meeting: the later one.
      if (const std::int32_t k = std::max(owner[f], owner[g]); k >= 0) undo.insert(k);
    }
    check.clear();
    for (std::int32_t k : undo) {
      for (int i = 0; i < 2; ++i) {
        const std::uint32_t f = made[std::size_t(k)].faces[i];
        s.faces[f] = made[std::size_t(k)].old[i];
        faces[f] = {s.faces[f].x, s.faces[f].y, s.faces[f].z};
        owner[f] = -1;
        check.push_back(f);
      }
      ++undone;
    }
  }
  if (undone < made.size()) rebuild_after_flips(s);  // all undone: S is as it was, adjacency too
  return made.size() - undone;
}

}  // namespace fracref
