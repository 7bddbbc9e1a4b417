// find_step_collisions of ccd.hpp (a mesh against itself): swept-box broad phase, then the
// exact-bounded narrow phase; and the helpers it shares with ccd_static.cpp.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "geom/bvh.hpp"
#include "geom/ccd.hpp"
#include "geom/bvh_traverse.hpp"
#include "geom/ccd_mesh_internal.hpp"
#include "geom/slabs.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace ccd_detail {

void check_positions(const std::vector<dvec3>& x, const char* what) {
  for (std::size_t v = 0; v < x.size(); ++v)
    if (!std::isfinite(x[v].x) || !std::isfinite(x[v].y) || !std::isfinite(x[v].z))
      throw InputError(std::string(what) + " vertex " + std::to_string(v) + ": coordinate is not finite");
}

void check_triangles(const Tris& tris, std::size_t n, const char* what) {
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (std::uint32_t v : tris[t])
      if (v >= n)
        throw InputError(std::string(what) + " triangle " + std::to_string(t) + ": vertex index " + std::to_string(v) +
                         " out of range (" + std::to_string(n) + " vertices)");
}

// Sorted unique edges (a < b) by a counting sort on a, then a sort of each (short) bucket: linear
// in the triangle count, where one sort of all 3t half-edges dominated the static CCD's cost.
std::vector<Edge> unique_edges(const Tris& tris) {
  std::uint32_t n = 0;
  for (const auto& t : tris) n = std::max({n, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<std::uint32_t> start(std::size_t(n) + 1, 0);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k)
      if (t[k] != t[(k + 1) % 3]) ++start[std::min(t[k], t[(k + 1) % 3]) + 1];
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1), other(start[n]);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a != b) other[fill[std::min(a, b)]++] = std::max(a, b);
    }
  std::vector<Edge> edges;
  edges.reserve(other.size() / 2 + 1);
  for (std::uint32_t a = 0; a < n; ++a) {
    const auto first = other.begin() + start[a], last = other.begin() + start[a + 1];
    std::sort(first, last);
    for (auto it = first; it != last; ++it)
      if (it == first || *it != *(it - 1)) edges.push_back({a, *it});
  }
  return edges;
}

// Each vertex's travel over the step, as ccd_vertex_triangle and ccd_edge_edge compute it: once
// per vertex instead of once per corner of every pair tested.
std::vector<double> travels(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, int threads) {
  std::vector<double> out(x0.size());
  parallel_chunks(x0.size(), chunk_count(x0.size(), 8192), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) out[v] = glm::length(x1[v] - x0[v]);
  });
  return out;
}

std::vector<std::array<std::uint32_t, 1>> used_vertices(const Tris& tris, std::size_t n) {
  std::vector<char> used(n, 0);
  for (const auto& t : tris)
    for (std::uint32_t v : t) used[v] = 1;
  std::vector<std::array<std::uint32_t, 1>> out;
  for (std::size_t v = 0; v < n; ++v)
    if (used[v]) out.push_back({static_cast<std::uint32_t>(v)});
  return out;
}

CcdPair vertex_pair(CcdKind kind, std::uint32_t v, const std::array<std::uint32_t, 3>& tri, std::uint32_t t) {
  return {kind, {v, tri[0], tri[1], tri[2]}, t};
}

// Whether vertex v takes part in the pairs to test (StepCcdOptions::active_vertices and
// skip_resting_pairs).
bool is_active(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, const StepCcdOptions& o, std::size_t v) {
  if (o.active_vertices) return (*o.active_vertices)[v] != 0;
  return !o.skip_resting_pairs || x0[v] != x1[v];
}

void check_flags(const std::vector<std::uint8_t>* flags, std::size_t n, const char* what) {
  if (flags && flags->size() != n)
    throw InputError("step collisions: " + std::to_string(flags->size()) + " " + what + " flags for " +
                     std::to_string(n) + " vertices");
}

}  // namespace ccd_detail

namespace {

using namespace ccd_detail;

// Leaves of 16 boxes: on a large surface the broad phase is most of a call's cost, and a
// shallower tree visits fewer nodes; the slabs' test after the boxes' (cheap, on slot data read
// in order) makes the larger leaves' extra pair tests cheap.
constexpr std::uint32_t kLeaf = 16;

// Which vertices, triangles and edges move over the step; with `all_moving` every used vertex
// and every element counts as moving (the exhaustive test).
struct Motion {
  std::vector<std::uint32_t> moving_vertices, resting_vertices;
  std::vector<std::uint32_t> moving_triangles, resting_triangles;  // only filled when some used vertex rests
  std::vector<std::uint32_t> moving_edges, resting_edges;
};

Motion classify_motion(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, const Tris& tris,
                       const std::vector<Edge>& edges, const StepCcdOptions& options) {
  std::vector<std::uint8_t> state(x0.size(), 0);  // bit 0: used, bit 1: active
  for (const auto& t : tris)
    for (std::uint32_t v : t) state[v] = 1;
  Motion m;
  for (std::size_t v = 0; v < x0.size(); ++v) {
    if (!state[v]) continue;
    if (is_active(x0, x1, options, v)) state[v] |= 2;
    ((state[v] & 2) ? m.moving_vertices : m.resting_vertices).push_back(std::uint32_t(v));
  }
  auto moves = [&](std::uint32_t v) { return (state[v] & 2) != 0; };
  if (!m.resting_vertices.empty())
    for (std::uint32_t t = 0; t < tris.size(); ++t)
      (moves(tris[t][0]) || moves(tris[t][1]) || moves(tris[t][2]) ? m.moving_triangles : m.resting_triangles).push_back(t);
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    ((moves(edges[e][0]) || moves(edges[e][1])) ? m.moving_edges : m.resting_edges).push_back(e);
  return m;
}

// Builds trees over the swept boxes of subsets of a mesh's elements (tree item k = subset[k]).
struct StepTrees {
  const std::vector<dvec3>& x0;
  const std::vector<dvec3>& x1;
  const std::vector<double>& travel;  // |x1 - x0| per vertex
  const std::vector<Slabs>& slabs;    // per vertex, of its path (vertex_slabs)
  double grow;
  int threads;

  // `with` threads build the tree (the tree does not depend on it).
  template <std::size_t N>
  Bvh build(const std::vector<std::array<std::uint32_t, N>>& elements, const std::vector<std::uint32_t>* subset,
            double g, int with) const {
    return tree(subset ? subset->size() : elements.size(), with,
                [&](std::size_t k) { return swept_box(x0, x1, elements[subset ? (*subset)[k] : k], g); });
  }
  Bvh vertices(const std::vector<std::uint32_t>& ids, int with) const {
    return tree(ids.size(), with,
                [&](std::size_t k) { return swept_box(x0, x1, std::array<std::uint32_t, 1>{ids[k]}, 0.0); });
  }
  // The tree over box(0 .. n-1), the boxes computed on the threads too.
  template <class Box>
  Bvh tree(std::size_t n, int with, const Box& box) const {
    std::vector<Aabb> boxes(n);
    parallel_chunks(n, chunk_count(n, 4096), with, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) boxes[k] = box(k);
    });
    BvhOptions o;
    o.leaf_size = kLeaf;
    o.threads = with;
    return build_bvh(boxes, o);
  }
};

// A tree's items renumbered in leaf order (slots), with each slot's element id, its vertices and
// the slabs of their paths: the broad phase's last filters read them front to back.
template <std::size_t N>
struct Slots {
  std::vector<std::uint32_t> ids;
  std::vector<std::array<std::uint32_t, N>> elements;
  std::vector<Slabs> slabs;
};

// `element(id)` gives an element's vertices; `subset` maps tree items to ids (null: identity).
template <std::size_t N, class Element>
Slots<N> number_slots(Bvh& tree, const std::vector<std::uint32_t>* subset, const std::vector<Slabs>& vertex_slabs,
                      const Element& element) {
  Slots<N> s;
  s.ids = number_items_in_leaf_order(tree);
  s.elements.resize(s.ids.size());
  s.slabs.resize(s.ids.size());
  for (std::size_t k = 0; k < s.ids.size(); ++k) {
    if (subset) s.ids[k] = (*subset)[s.ids[k]];
    s.elements[k] = element(s.ids[k]);
    for (std::uint32_t v : s.elements[k]) merge(s.slabs[k], vertex_slabs[v]);
  }
  return s;
}

template <std::size_t A, std::size_t B>
bool share_vertex(const std::array<std::uint32_t, A>& a, const std::array<std::uint32_t, B>& b) {
  for (std::uint32_t v : a)
    for (std::uint32_t w : b)
      if (v == w) return true;
  return false;
}

// Each vertex's path over the step as Slabs, padded so that primitives whose slabs are apart stay
// more than 4 (tolerance + min_distance) apart. The narrow phase reports no pair beyond
// sqrt(3) (tolerance + min_distance + its rounding bound, 162 u per unit of the largest
// coordinate; 256 u here), so the slabs only drop pairs it would clear, with a margin for the
// pairs it gives up on (those rest within a few tolerances).
std::vector<Slabs> vertex_slabs(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, const CcdOptions& ccd,
                                int threads) {
  double largest = 0.0;
  for (std::size_t v = 0; v < x0.size(); ++v) {
    const dvec3 m = glm::max(glm::abs(x0[v]), glm::abs(x1[v]));
    largest = std::max(largest, std::max(m.x, std::max(m.y, m.z)));
  }
  const double pad = 2.0 * (std::max(0.0, ccd.min_distance) + ccd.tolerance) + 0x1p-45 * largest;
  std::vector<Slabs> out(x0.size());
  parallel_chunks(x0.size(), chunk_count(x0.size(), 8192), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) out[v] = segment_slabs(x0[v], x1[v], pad);
  });
  return out;
}

// When few elements take part (a later round, or a step that moves a few new vertices), a tree
// over all the others would cost more than the tests: instead each of the many boxes is
// queried against a tree over the few. Calls test(k, j, out) for every overlapping pair of
// few[k] and many_box(j), j < many.
template <class R, class ManyBox, class Test>
std::vector<R> scan_against(const std::vector<Aabb>& few, std::size_t many, ManyBox many_box, int threads, Test test) {
  if (few.empty() || many == 0) return {};
  const Bvh tree = build_bvh(few);
  const std::size_t chunks = chunk_count(many);
  std::vector<std::vector<R>> parts(chunks);
  parallel_chunks(many, chunks, threads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t> hits;
    for (std::size_t j = begin; j < end; ++j) {
      hits.clear();
      query_box(tree, many_box(j), hits);
      for (std::uint32_t k : hits) test(k, std::uint32_t(j), parts[c]);
    }
  });
  std::vector<R> out;
  for (auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

// A pair the narrow phase took past its distance filter, with its answer. Only colliding pairs
// are kept unless the caller asked for the examined ones (StepCcdOptions::examined).
struct Examined {
  CcdPair pair;
  bool collides = false;
};

// Tests a vertex-triangle pair, recording it as above.
void test_vertex_triangle(const StepTrees& trees, std::uint32_t v, const std::array<std::uint32_t, 3>& tri,
                          std::uint32_t t, const CcdOptions& ccd, bool record, std::vector<Examined>& found) {
  const auto& x0 = trees.x0;
  const auto& x1 = trees.x1;
  const auto& r = trees.travel;
  const double travel[4] = {r[v], r[tri[0]], r[tri[1]], r[tri[2]]};
  CcdStats stats;
  const bool hit = ccd_vertex_triangle(x0[v], x0[tri[0]], x0[tri[1]], x0[tri[2]], x1[v], x1[tri[0]], x1[tri[1]],
                                       x1[tri[2]], travel, ccd, &stats);
  if (hit || (record && stats.near)) found.push_back({vertex_pair(CcdKind::vertex_triangle, v, tri, t), hit});
}

// Tests an edge-edge pair, e < f, recording it as above.
void test_edge_edge(const StepTrees& trees, const Edge& e, const Edge& f, const CcdOptions& ccd, bool record,
                    std::vector<Examined>& found) {
  const auto& x0 = trees.x0;
  const auto& x1 = trees.x1;
  const auto& r = trees.travel;
  const double travel[4] = {r[e[0]], r[e[1]], r[f[0]], r[f[1]]};
  CcdStats stats;
  const bool hit = ccd_edge_edge(x0[e[0]], x0[e[1]], x0[f[0]], x0[f[1]], x1[e[0]], x1[e[1]], x1[f[0]], x1[f[1]], travel,
                                 ccd, &stats);
  if (hit || (record && stats.near))
    found.push_back({{CcdKind::edge_edge, {e[0], e[1], f[0], f[1]}, CcdPair::kNoTriangle}, hit});
}

constexpr std::size_t kSparseFactor = 16;  // "few": under 1/16 of the elements take part

// A tree over some of the mesh's elements, its items numbered in leaf order.
template <std::size_t N>
struct SlotTree {
  Bvh tree;
  Slots<N> slots;
};

// The pairs of a's and b's elements whose boxes overlap, that share no vertex and whose slabs
// are not apart (with `self`, b is a and each unordered pair comes once):
// test(id in a, its vertices, id in b, its vertices, found).
template <std::size_t A, std::size_t B, class Test>
std::vector<Examined> slot_pairs(const SlotTree<A>& a, const SlotTree<B>& b, bool self, int threads, const Test& test) {
  return collect_overlaps<Examined, BoxTest::float_rounded>(a.tree, b.tree, self, threads,
                                    [&](std::uint32_t i, std::uint32_t j, std::vector<Examined>& found) {
                                      const auto& ea = a.slots.elements[i];
                                      const auto& eb = b.slots.elements[j];
                                      if (share_vertex(ea, eb) || slabs_apart(a.slots.slabs[i], b.slots.slabs[j])) return;
                                      test(a.slots.ids[i], ea, b.slots.ids[j], eb, found);
                                    });
}

// The trees of a search, built before its traversals: each build on one thread (a build's own
// two threads leave its serial parts, the sort's counts, the allocations, on one core), the
// largest first, each onto the thread with less work so far: one tree (the triangles') can be as
// large as all the others together. The trees do not depend on the schedule.
class TreeBuilds {
 public:
  void add(std::size_t size, std::function<void()> build) { builds_.push_back({size, std::move(build)}); }
  void run(int threads) {
    std::stable_sort(builds_.begin(), builds_.end(), [](const Build& a, const Build& b) { return a.size > b.size; });
    const std::size_t lanes = threads >= 2 ? 2 : 1;
    std::vector<std::vector<const Build*>> lane(lanes);
    std::vector<std::size_t> load(lanes, 0);
    for (const Build& b : builds_) {
      const std::size_t l = std::min_element(load.begin(), load.end()) - load.begin();
      lane[l].push_back(&b);
      load[l] += b.size;
    }
    parallel_chunks(lanes, lanes, threads, [&](std::size_t l, std::size_t, std::size_t) {
      for (const Build* b : lane[l]) b->build();
    });
  }

 private:
  struct Build {
    std::size_t size;
    std::function<void()> build;
  };
  std::vector<Build> builds_;
};

// Plans the tree over elements (or the subset of them) grown by g.
template <std::size_t N>
void plan_tree(const StepTrees& trees, TreeBuilds& builds, SlotTree<N>& out,
               const std::vector<std::array<std::uint32_t, N>>& elements, const std::vector<std::uint32_t>* subset,
               double g) {
  builds.add(subset ? subset->size() : elements.size(), [&trees, &out, &elements, subset, g] {
    out.tree = trees.build(elements, subset, g, 1);
    out.slots = number_slots<N>(out.tree, subset, trees.slabs, [&](std::uint32_t id) { return elements[id]; });
  });
}

void plan_vertex_tree(const StepTrees& trees, TreeBuilds& builds, SlotTree<1>& out,
                      const std::vector<std::uint32_t>& ids) {
  builds.add(ids.size(), [&trees, &out, &ids] {
    out.tree = trees.vertices(ids, 1);
    out.slots = number_slots<1>(out.tree, &ids, trees.slabs, [](std::uint32_t v) { return std::array<std::uint32_t, 1>{v}; });
  });
}

// The vertex-triangle search: moving vertices against all triangles, resting vertices against
// the moving triangles; with few moving vertices, scans instead of trees. When some vertices
// rest, the triangles' tree is two, over the moving and the resting ones: the moving
// triangles' tree serves both kinds of vertex, and no triangle is built into two trees.
struct VertexTriangleSearch {
  const StepTrees& trees;
  const Tris& tris;
  const Motion& m;
  SlotTree<3> triangles, moving_triangles, resting_triangles;
  SlotTree<1> moving_vertices, resting_vertices;

  bool sparse() const {
    return m.moving_vertices.size() * kSparseFactor < m.moving_vertices.size() + m.resting_vertices.size();
  }
  bool some_rest() const { return !m.resting_vertices.empty(); }
  void plan(TreeBuilds& builds) {
    if (sparse()) return;
    plan_vertex_tree(trees, builds, moving_vertices, m.moving_vertices);
    if (!some_rest()) return plan_tree(trees, builds, triangles, tris, nullptr, trees.grow);
    plan_vertex_tree(trees, builds, resting_vertices, m.resting_vertices);
    plan_tree(trees, builds, moving_triangles, tris, &m.moving_triangles, trees.grow);
    plan_tree(trees, builds, resting_triangles, tris, &m.resting_triangles, trees.grow);
  }
  // \pre the planned trees are built.
  std::vector<Examined> pairs(const CcdOptions& ccd, bool record) const {
    auto test = [&](std::uint32_t v, std::uint32_t t, std::vector<Examined>& found) {
      const auto& tri = tris[t];
      if (share_vertex(std::array<std::uint32_t, 1>{v}, tri)) return;
      test_vertex_triangle(trees, v, tri, t, ccd, record, found);
    };
    if (sparse()) return scans(test);
    auto tested = [&](std::uint32_t v, const std::array<std::uint32_t, 1>&, std::uint32_t t,
                      const std::array<std::uint32_t, 3>& tri, std::vector<Examined>& found) {
      test_vertex_triangle(trees, v, tri, t, ccd, record, found);
    };
    if (!some_rest()) return slot_pairs(moving_vertices, triangles, false, trees.threads, tested);
    auto out = slot_pairs(moving_vertices, moving_triangles, false, trees.threads, tested);
    auto more = slot_pairs(moving_vertices, resting_triangles, false, trees.threads, tested);
    out.insert(out.end(), more.begin(), more.end());
    more = slot_pairs(resting_vertices, moving_triangles, false, trees.threads, tested);
    out.insert(out.end(), more.begin(), more.end());
    return out;
  }
  template <class Test>
  std::vector<Examined> scans(const Test& test) const {
    const auto& x0 = trees.x0;
    const auto& x1 = trees.x1;
    std::vector<Aabb> few(m.moving_vertices.size());
    for (std::size_t k = 0; k < few.size(); ++k) few[k] = swept_box(x0, x1, std::array<std::uint32_t, 1>{m.moving_vertices[k]}, 0.0);
    auto out = scan_against<Examined>(
        few, tris.size(), [&](std::size_t t) { return swept_box(x0, x1, tris[t], trees.grow); }, trees.threads,
        [&](std::uint32_t k, std::uint32_t t, std::vector<Examined>& found) { test(m.moving_vertices[k], t, found); });
    std::vector<Aabb> few_tris(m.moving_triangles.size());
    for (std::size_t k = 0; k < few_tris.size(); ++k) few_tris[k] = swept_box(x0, x1, tris[m.moving_triangles[k]], trees.grow);
    auto rest = scan_against<Examined>(
        few_tris, m.resting_vertices.size(),
        [&](std::size_t j) { return swept_box(x0, x1, std::array<std::uint32_t, 1>{m.resting_vertices[j]}, 0.0); },
        trees.threads,
        [&](std::uint32_t k, std::uint32_t j, std::vector<Examined>& found) {
          test(m.resting_vertices[j], m.moving_triangles[k], found);
        });
    out.insert(out.end(), rest.begin(), rest.end());
    return out;
  }
};

// The edge-edge search: moving edges against each other and against the resting ones; with few
// moving edges, a scan instead of trees. Both sides are grown by half the distance: boxes of
// edges closer than min_distance overlap.
struct EdgeEdgeSearch {
  const StepTrees& trees;
  const std::vector<Edge>& edges;
  const Motion& m;
  SlotTree<2> moving, resting;

  bool sparse() const { return m.moving_edges.size() * kSparseFactor < edges.size(); }
  bool with_resting() const { return !m.resting_edges.empty() && !m.moving_edges.empty(); }
  void plan(TreeBuilds& builds) {
    if (sparse()) return;
    plan_tree(trees, builds, moving, edges, &m.moving_edges, 0.5 * trees.grow);
    if (with_resting()) plan_tree(trees, builds, resting, edges, &m.resting_edges, 0.5 * trees.grow);
  }
  // \pre the planned trees are built.
  std::vector<Examined> pairs(const CcdOptions& ccd, bool record) const {
    auto test = [&](std::uint32_t i, std::uint32_t j, std::vector<Examined>& found) {
      Edge e = edges[i], f = edges[j];
      if (share_vertex(e, f)) return;
      if (f < e) std::swap(e, f);
      test_edge_edge(trees, e, f, ccd, record, found);
    };
    if (sparse()) return scan(test);
    auto tested = [&](std::uint32_t, Edge e, std::uint32_t, Edge f, std::vector<Examined>& found) {
      if (f < e) std::swap(e, f);
      test_edge_edge(trees, e, f, ccd, record, found);
    };
    auto out = slot_pairs(moving, moving, true, trees.threads, tested);
    if (!with_resting()) return out;
    auto rest = slot_pairs(moving, resting, false, trees.threads, tested);
    out.insert(out.end(), rest.begin(), rest.end());
    return out;
  }
  template <class Test>
  std::vector<Examined> scan(const Test& test) const {
    const auto& x0 = trees.x0;
    const auto& x1 = trees.x1;
    std::vector<char> moves(edges.size(), 0);
    std::vector<Aabb> few(m.moving_edges.size());
    for (std::size_t k = 0; k < few.size(); ++k) {
      moves[m.moving_edges[k]] = 1;
      few[k] = swept_box(x0, x1, edges[m.moving_edges[k]], 0.5 * trees.grow);
    }
    // A pair of two moving edges is met from both sides: kept once, from its smaller id.
    return scan_against<Examined>(
        few, edges.size(), [&](std::size_t j) { return swept_box(x0, x1, edges[j], 0.5 * trees.grow); }, trees.threads,
        [&](std::uint32_t k, std::uint32_t j, std::vector<Examined>& found) {
          const std::uint32_t i = m.moving_edges[k];
          if (i == j || (moves[j] && j < i)) return;
          test(i, j, found);
        });
  }
};

// The pairs of `candidates` with an active vertex whose swept boxes overlap (as the broad phase
// would have found them), tested as above.
std::vector<Examined> candidate_pairs(const StepTrees& trees, const std::vector<CcdPair>& candidates,
                                      const StepCcdOptions& o, bool record) {
  std::vector<Examined> out;
  for (const CcdPair& c : candidates) {
    const auto& v = c.vertices;
    if (!std::any_of(v.begin(), v.end(), [&](std::uint32_t k) { return is_active(trees.x0, trees.x1, o, k); }))
      continue;
    if (c.kind == CcdKind::edge_edge) {
      const Edge e{v[0], v[1]}, f{v[2], v[3]};
      if (swept_box(trees.x0, trees.x1, e, 0.5 * trees.grow)
              .overlaps(swept_box(trees.x0, trees.x1, f, 0.5 * trees.grow)))
        test_edge_edge(trees, e, f, o.ccd, record, out);
      continue;
    }
    const std::array<std::uint32_t, 3> tri{v[1], v[2], v[3]};
    if (swept_box(trees.x0, trees.x1, std::array<std::uint32_t, 1>{v[0]}, 0.0)
            .overlaps(swept_box(trees.x0, trees.x1, tri, trees.grow)))
      test_vertex_triangle(trees, v[0], tri, c.triangle, o.ccd, record, out);
  }
  return out;
}

}  // namespace

std::vector<CcdPair> find_step_collisions(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1,
                                          const Tris& triangles, const StepCcdOptions& options) {
  if (x0.size() != x1.size())
    throw InputError("step collisions: " + std::to_string(x0.size()) + " start positions but " +
                     std::to_string(x1.size()) + " end positions");
  check_positions(x0, "start");
  check_positions(x1, "end");
  check_triangles(triangles, x0.size(), "mesh");
  check_flags(options.active_vertices, x0.size(), "active-vertex");
  const std::vector<double> travel = travels(x0, x1, options.threads);
  const std::vector<Slabs> slabs =
      options.candidates ? std::vector<Slabs>() : vertex_slabs(x0, x1, options.ccd, options.threads);
  StepTrees trees{x0, x1, travel, slabs, std::max(0.0, options.ccd.min_distance), options.threads};
  const bool record = options.examined != nullptr;
  std::vector<Examined> found;
  if (options.candidates) {
    found = candidate_pairs(trees, *options.candidates, options, record);
  } else {
    const std::vector<Edge> own_edges = options.edges ? std::vector<Edge>() : unique_edges(triangles);
    const std::vector<Edge>& edges = options.edges ? *options.edges : own_edges;
    const Motion motion = classify_motion(x0, x1, triangles, edges, options);
    VertexTriangleSearch vertex_triangle{trees, triangles, motion, {}, {}, {}, {}, {}};
    EdgeEdgeSearch edge_edge{trees, edges, motion, {}, {}};
    TreeBuilds builds;
    vertex_triangle.plan(builds);
    edge_edge.plan(builds);
    builds.run(options.threads);
    found = vertex_triangle.pairs(options.ccd, record);
    std::vector<Examined> ee = edge_edge.pairs(options.ccd, record);
    found.insert(found.end(), ee.begin(), ee.end());
  }
  std::vector<CcdPair> out;
  if (options.examined) options.examined->clear();
  for (const Examined& e : found) {
    if (e.collides) out.push_back(e.pair);
    if (options.examined) options.examined->push_back(e.pair);
  }
  if (options.examined) std::sort(options.examined->begin(), options.examined->end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fracref
