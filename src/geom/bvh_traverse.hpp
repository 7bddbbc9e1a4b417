#pragma once
// Simultaneous traversal of two AABB trees (or one tree against itself), split into tasks
// that run on a few threads. Cheaper than one box query per item: nearby items share descents.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "geom/bvh.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// What a traversal's pairs satisfy: their boxes overlap, or (cheaper: no double test after the
/// float one) their boxes rounded outward to float do, a superset by at most the rounding of the
/// boxes (a few pairs in ten thousand), for tests that decide each pair exactly anyway.
enum class BoxTest { exact, float_rounded };

namespace geom_detail {

struct NodePair {
  std::uint32_t a, b;
};

inline double longest_side(const Aabb& box) {
  const glm::dvec3 e = box.hi - box.lo;
  return std::max(e.x, std::max(e.y, e.z));
}

// Splits one node pair into the pairs of its children; self pairs (x, x) split into (l, l),
// (r, r), (l, r). Returns false for two leaves.
[[gnu::always_inline]] inline bool expand(const Bvh& a, const Bvh& b, bool self, NodePair p, std::vector<NodePair>& out) {
  const BvhNode& x = a.nodes[p.a];
  const BvhNode& y = b.nodes[p.b];
  if (x.count > 0 && y.count > 0) return false;
  if (self && p.a == p.b) {
    out.push_back({x.first, x.first});
    out.push_back({x.first + 1, x.first + 1});
    out.push_back({x.first, x.first + 1});
  } else if (y.count > 0 || (x.count == 0 && longest_side(x.box) >= longest_side(y.box))) {
    out.push_back({x.first, p.b});
    out.push_back({x.first + 1, p.b});
  } else {
    out.push_back({p.a, y.first});
    out.push_back({p.a, y.first + 1});
  }
  return true;
}

// The query box rounded outward to float, as FloatLeafBoxes holds its boxes.
struct FloatBox {
  float lo[3], hi[3];
};

inline FloatBox float_box(const FloatLeafBoxes& f, std::uint32_t k) {
  return {{f.lo[0][k], f.lo[1][k], f.lo[2][k]}, {f.hi[0][k], f.hi[1][k], f.hi[2][k]}};
}

// Bit l set when box q and the float box at base + l overlap (closed), l < kLanes. A superset
// of the double boxes' overlaps, as the float boxes contain them.
inline unsigned float_overlap_mask(const FloatLeafBoxes& f, std::uint32_t base, const FloatBox& q) {
#if defined(__SSE2__)
  unsigned mask = 0;
  for (std::uint32_t half = 0; half < FloatLeafBoxes::kLanes; half += 4) {
    __m128 in = _mm_castsi128_ps(_mm_set1_epi32(-1));
    for (int a = 0; a < 3; ++a) {
      in = _mm_and_ps(in, _mm_cmple_ps(_mm_loadu_ps(&f.lo[a][base + half]), _mm_set1_ps(q.hi[a])));
      in = _mm_and_ps(in, _mm_cmple_ps(_mm_set1_ps(q.lo[a]), _mm_loadu_ps(&f.hi[a][base + half])));
    }
    mask |= unsigned(_mm_movemask_ps(in)) << half;
  }
  return mask;
#else
  unsigned mask = 0;
  for (std::uint32_t l = 0; l < FloatLeafBoxes::kLanes; ++l) {
    bool in = true;
    for (int a = 0; a < 3; ++a) in = in && f.lo[a][base + l] <= q.hi[a] && q.lo[a] <= f.hi[a][base + l];
    mask |= unsigned(in) << l;
  }
  return mask;
#endif
}

// Every pair of a leaf's item and b leaf's item whose boxes overlap, in the order of a plain
// double loop: a float test of each a box against b's boxes kLanes at a time, then (kTest exact)
// the double test of those it lets through.
template <BoxTest kTest, class Visit>
void visit_leaves(const Bvh& a, const Bvh& b, bool self, NodePair p, Visit& visit) {
  constexpr std::uint32_t kLanes = FloatLeafBoxes::kLanes;
  const BvhNode& x = a.nodes[p.a];
  const BvhNode& y = b.nodes[p.b];
  const std::uint32_t end = y.first + y.count;
  for (std::uint32_t k = x.first; k < x.first + x.count; ++k) {
    const std::uint32_t i = a.items[k];
    const Aabb& box = a.leaf_boxes[k];
    const FloatBox q = float_box(a.float_boxes, k);
    const std::uint32_t l0 = self && p.a == p.b ? k + 1 : y.first;
    for (std::uint32_t base = l0; base < end; base += kLanes) {
      unsigned mask = float_overlap_mask(b.float_boxes, base, q);
      if (end - base < kLanes) mask &= (1u << (end - base)) - 1u;
      while (mask != 0) {
        const std::uint32_t l = base + std::uint32_t(__builtin_ctz(mask));
        mask &= mask - 1u;
        if (kTest == BoxTest::exact && !box.overlaps(b.leaf_boxes[l])) continue;
        const std::uint32_t j = b.items[l];
        if (self)
          visit(std::min(i, j), std::max(i, j));
        else
          visit(i, j);
      }
    }
  }
}

// Whether the traversal must look into node pair p: the boxes overlap (a node with itself does).
inline bool worth_visiting(const Bvh& a, const Bvh& b, bool self, NodePair p) {
  return (self && p.a == p.b) || a.nodes[p.a].box.overlaps(b.nodes[p.b].box);
}

template <BoxTest kTest, class Visit>
void traverse_from(const Bvh& a, const Bvh& b, bool self, NodePair start, Visit& visit) {
  std::vector<NodePair> stack{start};
  while (!stack.empty()) {
    const NodePair p = stack.back();
    stack.pop_back();
    if (!worth_visiting(a, b, self, p)) continue;
    if (!expand(a, b, self, p, stack)) visit_leaves<kTest>(a, b, self, p, visit);
  }
}

}  // namespace geom_detail

/// Calls test(i, j, out) for every pair of items with overlapping (closed) boxes: i in `a` and
/// j in `b`, or, when `self` (b must then be a), every unordered pair once as i < j; with
/// BoxTest::float_rounded, for every pair whose boxes rounded outward to float overlap. The work
/// is split into tasks run on `threads` threads; the returned concatenation of the `out`
/// vectors has a deterministic order (independent of `threads`) but is not sorted.
template <class R, BoxTest kTest = BoxTest::exact, class Test>
std::vector<R> collect_overlaps(const Bvh& a, const Bvh& b, bool self, int threads, Test&& test) {
  using geom_detail::NodePair;
  if (a.nodes.empty() || b.nodes.empty()) return {};
  // Breadth-first expansion of the root pair into enough tasks for load balance.
  std::vector<NodePair> tasks{{0, 0}}, next;
  std::vector<NodePair> leaves;  // pairs of two leaves met during the expansion
  while (!tasks.empty() && tasks.size() < 256) {
    next.clear();
    for (const NodePair& p : tasks) {
      if (!geom_detail::worth_visiting(a, b, self, p)) continue;
      if (!geom_detail::expand(a, b, self, p, next)) leaves.push_back(p);
    }
    tasks.swap(next);
  }
  tasks.insert(tasks.end(), leaves.begin(), leaves.end());
  std::vector<std::vector<R>> parts(tasks.size());
  parallel_chunks(tasks.size(), tasks.size(), threads, [&](std::size_t c, std::size_t, std::size_t) {
    auto visit = [&](std::uint32_t i, std::uint32_t j) { test(i, j, parts[c]); };
    geom_detail::traverse_from<kTest>(a, b, self, tasks[c], visit);
  });
  std::vector<R> out;
  for (auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

}  // namespace fracref
