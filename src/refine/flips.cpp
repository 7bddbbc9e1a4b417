#include "refine/flips.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "geom/bvh.hpp"
#include "geom/bvh_traverse.hpp"
#include "geom/intersect.hpp"
#include "geom/quad_prism.hpp"
#include "util/key_set.hpp"
#include "util/parallel.hpp"

#include "refine/junction_order.hpp"
#include "refine/topology_edit.hpp"

namespace fracref {

namespace {

// Leaves of 8, as the CCD's trees: the check after the pass is mostly box traversal, which
// smaller leaves shorten.
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

// A flip that passes every test that does not depend on the pass's earlier flips.
struct FlipCandidate {
  std::uint32_t edge;
  glm::uvec2 opposite, faces;
  std::array<std::uint32_t, 4> junctions;  // the quad's outer junction edges, kNoEdge after them
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
      if (!(slim[f1] || slim[f2]) || !flip_quad(s, e, cd, ff)) continue;
      const glm::uvec2 ab = s.edges[e];
      const Quad q{x(ab.x), x(ab.y), x(cd.x), x(cd.y), samples[ab.x].x, samples[ab.y].x, samples[cd.x].x, samples[cd.y].x};
      // The edge table's search last: a fifth of the quads get past flip_improves.
      std::array<std::uint32_t, 4> junctions{};
      if (flip_improves(q, o) && find_edge(s, cd.x, cd.y) == kNoEdge &&
          flip_keeps_junction_order(s, e, cd, ff, junctions))
        parts[c].push_back({e, cd, ff, junctions});
    }
  });
  std::vector<FlipCandidate> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

// Each flip's new faces lie in the tetrahedron of its quad: a face that its QuadPrism separates
// from the quad meets neither of them, and needs no exact test (most of the pairs met in the
// check below).
//
// The check works flip by flip: one box per flip (its quad's, the union of its two new faces'
// boxes) met with a tree over the other faces of S, one prism test per flip and face, then the
// exact test of each new face whose own box meets the face's. Face by face (a tree over the new
// faces) would meet more box pairs and run each prism test twice. What a pair reads is gathered per tree slot (number_items_in_leaf_order): read
// through face ids, each pair cost a few cache misses, more than its tests.
class FlipCheck {
 public:
  // `flip_faces`: per flip, its two new faces, as they stand in `faces`; `quads`: per flip, its
  // corners in order around the quad. Reads `faces` at every call: undone flips' faces restored.
  FlipCheck(const std::vector<glm::dvec3>& x, const std::vector<TriangleIds>& faces,
            const std::vector<std::array<std::uint32_t, 2>>& flip_faces, const std::vector<std::array<std::uint32_t, 4>>& quads,
            const std::vector<char>& flipped, int threads)
      : x_(x), faces_(faces), threads_(threads) {
    const std::vector<Aabb> boxes = triangle_boxes(x, faces, threads);
    std::vector<std::uint32_t> others;
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      if (!flipped[f]) others.push_back(f);
    build_trees(boxes, flip_faces, others);
    flips_.resize(flip_ids_.size());
    // Small chunks: a slot's prism test is cheap, and a step makes few flips compared with faces.
    parallel_chunks(flips_.size(), chunk_count(flips_.size(), 256), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) flips_[k] = flip_slot(boxes, flip_faces[flip_ids_[k]], quads[flip_ids_[k]]);
    });
    others_.resize(other_ids_.size());
    parallel_chunks(others_.size(), chunk_count(others_.size(), 1024), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) {
        const TriangleIds& g = faces[other_ids_[j]];
        others_[j] = {g, {x[g[0]], x[g[1]], x[g[2]]}};
      }
    });
  }

  // The flips to undo for the first round: each whose new faces meet a face of S that is not
  // flipped, and the later of two whose new faces meet (a flip's own two faces included); sorted.
  std::vector<std::int32_t> first_round() const {
    std::vector<std::int32_t> out = collect_overlaps<std::int32_t, BoxTest::float_rounded>(
        flip_tree_, flip_tree_, true, threads_, [&](std::uint32_t k, std::uint32_t l, std::vector<std::int32_t>& found) {
          if (flips_meet(k, l)) found.push_back(std::int32_t(std::max(flip_ids_[k], flip_ids_[l])));
        });
    const std::vector<std::int32_t> rest = collect_overlaps<std::int32_t, BoxTest::float_rounded>(
        flip_tree_, other_tree_, false, threads_, [&](std::uint32_t k, std::uint32_t j, std::vector<std::int32_t>& found) {
          if (flip_meets(k, j)) found.push_back(std::int32_t(flip_ids_[k]));
        });
    out.insert(out.end(), rest.begin(), rest.end());
    const std::size_t chunks = chunk_count(flips_.size(), 1024);
    std::vector<std::vector<std::int32_t>> own(chunks);
    parallel_chunks(flips_.size(), chunks, threads_, [&](std::size_t c, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k)
        if (mesh_faces_intersect(x_, flips_[k].ids[0], flips_[k].ids[1])) own[c].push_back(std::int32_t(flip_ids_[k]));
    });
    for (const auto& part : own) out.insert(out.end(), part.begin(), part.end());
    return sorted_unique(std::move(out));
  }

  // The flips still made (`owner` of their faces >= 0) whose new faces meet one of `restored`
  // (faces just put back, as they now stand in `faces`); sorted. Restored faces meeting each
  // other or unflipped faces undo nothing: all of them were S's.
  std::vector<std::int32_t> meeting_restored(const std::vector<std::uint32_t>& restored, const std::vector<std::int32_t>& owner) const {
    std::vector<std::int32_t> out;
    std::vector<std::uint32_t> near;
    for (std::uint32_t r : restored) {
      Aabb box;
      for (std::uint32_t v : faces_[r]) box.expand(x_[v]);
      near.clear();
      query_box(flip_tree_, box, near);
      for (std::uint32_t k : near) {
        if (owner[flips_[k].faces[0]] < 0) continue;
        for (int i = 0; i < 2; ++i)
          if (flips_[k].boxes[i].overlaps(box) && mesh_faces_intersect(x_, flips_[k].ids[i], faces_[r])) {
            out.push_back(std::int32_t(flip_ids_[k]));
            break;
          }
      }
    }
    return sorted_unique(std::move(out));
  }

 private:
  // What the traversals read, gathered in the trees' leaf order.
  struct FlipSlot {
    std::array<std::uint32_t, 2> faces;
    std::array<TriangleIds, 2> ids;
    std::array<Aabb, 2> boxes;
    std::array<std::uint32_t, 4> quad;
    std::optional<QuadPrism> prism;
  };
  struct OtherSlot {
    TriangleIds ids;
    std::array<glm::dvec3, 3> p;
  };

  static std::vector<std::int32_t> sorted_unique(std::vector<std::int32_t> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
  }

  FlipSlot flip_slot(const std::vector<Aabb>& boxes, const std::array<std::uint32_t, 2>& faces,
                     const std::array<std::uint32_t, 4>& q) const {
    FlipSlot out{faces, {faces_[faces[0]], faces_[faces[1]]}, {boxes[faces[0]], boxes[faces[1]]}, q, std::nullopt};
    const std::array<glm::dvec3, 4> p = {x_[q[0]], x_[q[1]], x_[q[2]], x_[q[3]]};
    const glm::dvec3 n = glm::cross(p[2] - p[0], p[3] - p[1]);
    if (glm::length(n) > 0.0) out.prism.emplace(p, n);
    return out;
  }

  void build_trees(const std::vector<Aabb>& boxes, const std::vector<std::array<std::uint32_t, 2>>& flip_faces,
                   const std::vector<std::uint32_t>& others) {
    parallel_chunks(2, 2, threads_, [&](std::size_t t, std::size_t, std::size_t) {
      std::vector<Aabb> picked(t == 0 ? flip_faces.size() : others.size());
      for (std::size_t k = 0; k < picked.size(); ++k) {
        if (t == 1) {
          picked[k] = boxes[others[k]];
          continue;
        }
        picked[k] = boxes[flip_faces[k][0]];
        picked[k].expand(boxes[flip_faces[k][1]]);
      }
      BvhOptions o;
      o.leaf_size = kFlipTreeLeaf;
      Bvh& tree = t == 0 ? flip_tree_ : other_tree_;
      tree = build_bvh(picked, o);
      std::vector<std::uint32_t> order = number_items_in_leaf_order(tree);
      if (t == 0) {
        flip_ids_ = std::move(order);
      } else {
        for (std::uint32_t& k : order) k = others[k];
        other_ids_ = std::move(order);
      }
    });
  }

  // Whether flip k's prism separates the triangle with ids g and corners p from its quad.
  bool separated(const FlipSlot& k, const TriangleIds& g, const std::array<glm::dvec3, 3>& p) const {
    if (!k.prism) return false;
    std::array<int, 3> shared{-1, -1, -1};
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 4; ++c)
        if (g[i] == k.quad[c]) shared[i] = c;
    return k.prism->separates(p, shared);
  }

  // Whether a new face of flip k meets face j (slot of the tree over the faces not flipped).
  bool flip_meets(std::uint32_t k, std::uint32_t j) const {
    const FlipSlot& f = flips_[k];
    const Aabb& box = other_tree_.leaf_boxes[j];
    const bool near[2] = {f.boxes[0].overlaps(box), f.boxes[1].overlaps(box)};
    if (!(near[0] || near[1]) || separated(f, others_[j].ids, others_[j].p)) return false;
    for (int i = 0; i < 2; ++i)
      if (near[i] && mesh_faces_intersect(x_, f.ids[i], others_[j].ids)) return true;
    return false;
  }

  // Whether a new face of flip k meets one of flip l's.
  bool flips_meet(std::uint32_t k, std::uint32_t l) const {
    const FlipSlot &a = flips_[k], &b = flips_[l];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        if (!a.boxes[i].overlaps(b.boxes[j])) continue;
        const TriangleIds &f = a.ids[i], &g = b.ids[j];
        if (separated(a, g, {x_[g[0]], x_[g[1]], x_[g[2]]}) || separated(b, f, {x_[f[0]], x_[f[1]], x_[f[2]]})) continue;
        const bool f_first = a.faces[i] < b.faces[j];
        if (mesh_faces_intersect(x_, f_first ? f : g, f_first ? g : f)) return true;
      }
    return false;
  }

  const std::vector<glm::dvec3>& x_;
  const std::vector<TriangleIds>& faces_;
  int threads_;
  Bvh flip_tree_, other_tree_;            // items numbered in leaf order: slots
  std::vector<std::uint32_t> flip_ids_;   // per flip slot: the flip
  std::vector<std::uint32_t> other_ids_;  // per other slot: the face (of the faces not flipped)
  std::vector<FlipSlot> flips_;
  std::vector<OtherSlot> others_;
};

}  // namespace

std::size_t flip_slim_triangles(FractureSurface& s, std::span<const glm::vec4> samples, const ExteriorSurface&,
                                const FlipOptions& o) {
  const std::vector<FlipCandidate> candidates = candidate_flips(s, samples, o);
  if (candidates.empty()) return 0;
  // The flips are made first (in edge order, each face at most once) and checked afterwards: a
  // flip moves surface inside its quad when the quad is not flat, which can cut through a nearby
  // sheet of S. One pass of the new faces against all of S finds that; the later of two flips
  // whose faces meet, and a flip whose faces meet any other face, is undone, and the faces it
  // restores are checked in turn against the flips still made (they were S's, so they can meet
  // only those, so no tree over all of S is needed for them).
  // Checking each candidate's quad before its flip would test every nearby face against both new
  // faces of every candidate, almost all of which are accepted.
  struct Made {
    std::uint32_t faces[2];
    glm::uvec4 old[2];
  };
  std::vector<Made> made;
  std::vector<std::int32_t> owner(s.faces.size(), -1);  // face -> index in `made` while flipped
  std::vector<char> used(s.faces.size(), 0);
  // Junction edges around which a flip of this pass turned a face: each candidate's order was
  // judged with the other faces where they were, so a second turn about the same edge waits.
  std::vector<char> turned(s.edges.size(), 0);
  // Edges this pass made (the adjacency is stale), as (smaller id << 32 | larger id): a hash set,
  // as only membership is asked.
  KeySet created(candidates.size());  // keys are never 0: a diagonal joins two distinct vertices
  for (const FlipCandidate& c : candidates) {
    const auto [lo, hi] = std::minmax(c.opposite.x, c.opposite.y);
    const std::uint64_t diagonal = (std::uint64_t(lo) << 32) | hi;
    if (used[c.faces.x] || used[c.faces.y] || created.contains(diagonal)) continue;
    if (std::any_of(c.junctions.begin(), c.junctions.end(), [&](std::uint32_t g) { return g != kNoEdge && turned[g]; }))
      continue;
    const Made m{{c.faces.x, c.faces.y}, {s.faces[c.faces.x], s.faces[c.faces.y]}};
    // Neither face has changed since the candidate was found, nor has the (stale) edge table, so
    // flip_edge would find this very quad again: the flip is made from it directly.
    const glm::uvec2 e = s.edges[c.edge];
    const glm::uvec4 f0(c.opposite.x, e.x, c.opposite.y, 0u), f1(c.opposite.y, e.y, c.opposite.x, 0u);
    if (o.reject_diagonal && o.reject_diagonal(c.opposite.x, c.opposite.y)) continue;
    if (o.reject_face && (o.reject_face(f0) || o.reject_face(f1))) continue;
    s.faces[c.faces.x] = f0;
    s.faces[c.faces.y] = f1;
    created.insert(diagonal);
    used[c.faces.x] = used[c.faces.y] = 1;
    for (const std::uint32_t g : c.junctions)
      if (g != kNoEdge) turned[g] = 1;
    owner[c.faces.x] = owner[c.faces.y] = std::int32_t(made.size());
    made.push_back(m);
  }
  if (made.empty()) return 0;
  const std::vector<glm::dvec3> x = double_positions(s);
  std::vector<TriangleIds> faces = face_triangles(s);
  std::vector<char> flipped(faces.size(), 0);
  std::vector<std::array<std::uint32_t, 2>> flip_faces;
  std::vector<std::array<std::uint32_t, 4>> quads;  // new faces (c, a, d), (d, b, c): c, a, d, b
  for (const Made& m : made) {
    flipped[m.faces[0]] = flipped[m.faces[1]] = 1;
    flip_faces.push_back({m.faces[0], m.faces[1]});
    const TriangleIds &n0 = faces[m.faces[0]], &n1 = faces[m.faces[1]];
    quads.push_back({n0[0], n0[1], n0[2], n1[1]});
  }
  const FlipCheck check(x, faces, flip_faces, quads, flipped, o.threads);
  std::vector<std::int32_t> undo = check.first_round();
  std::size_t undone = 0;
  std::vector<std::uint32_t> restored;
  while (!undo.empty()) {
    restored.clear();
    for (std::int32_t k : undo) {
      for (int i = 0; i < 2; ++i) {
        const std::uint32_t f = made[std::size_t(k)].faces[i];
        s.faces[f] = made[std::size_t(k)].old[i];
        faces[f] = {s.faces[f].x, s.faces[f].y, s.faces[f].z};
        owner[f] = -1;
        restored.push_back(f);
      }
      ++undone;
    }
    undo = check.meeting_restored(restored, owner);
  }
  if (undone < made.size()) rebuild_after_flips(s);  // all undone: S is as it was, adjacency too
  return made.size() - undone;
}

}  // namespace fracref
