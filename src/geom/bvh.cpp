#include "geom/bvh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <utility>

#include "geom/bvh_traverse.hpp"
#include "geom/float_bounds.hpp"
#include "geom/morton.hpp"
#include "util/counting_sort.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

using glm::dvec3;

struct BuildTask {
  std::uint32_t node, begin, end;
};

// Items sorted by the Morton code of their box centre on a cube grid over the centres' bounds
// (ties by id). A node's items are a contiguous range of codes; it splits where the highest bit
// that differs within the range turns from 0 to 1: a spatial median along the longest axis first
// (the grid is a cube, so long axes carry the leading bits). Building is a sort and a binary
// search per node, much cheaper than partitioning at every level. A 1024-cell grid per
// axis (30-bit codes, three radix passes) is fine enough for the trees here: items sharing a cell
// split at the middle of their range, and the sort was most of the build with 63-bit codes.
struct Keyed {
  std::uint32_t code;
  std::uint32_t id;
};

constexpr int kGridBits = 10;

// Below this many items the builds run on one thread (a thread costs more than it saves).
constexpr std::size_t kParallelItems = 8192;

// Stable LSD radix sort, one counting sort per digit (its counting and placing split in two
// parts for a large tree: the same order as one part).
void radix_sort(std::vector<Keyed>& items, int threads) {
  constexpr int kBits = kGridBits, kPasses = 3;
  constexpr std::uint32_t kDigits = 1u << kBits, kMask = kDigits - 1;
  const std::size_t parts = threads >= 2 && items.size() >= kParallelItems ? 2 : 1;
  std::vector<Keyed> scratch(items.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = pass * kBits;
    counting_sort(
        items.size(), kDigits, parts,
        [&](std::size_t i, auto&& emit) { emit((items[i].code >> shift) & kMask, 0u); },
        [&](std::size_t i, std::uint32_t, std::uint32_t pos) { scratch[pos] = items[i]; });
    items.swap(scratch);
  }
}

std::vector<Keyed> morton_sorted(const std::vector<Aabb>& boxes, int threads) {
  const std::size_t parts = threads >= 2 && boxes.size() >= kParallelItems ? 2 : 1;
  std::vector<Aabb> part_bounds(parts);
  parallel_chunks(boxes.size(), parts, threads, [&](std::size_t p, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) part_bounds[p].expand(boxes[i].lo + boxes[i].hi);
  });
  Aabb bounds;
  for (const Aabb& b : part_bounds) bounds.expand(b);
  const dvec3 ext = bounds.hi - bounds.lo;
  const double side = std::max({ext.x, ext.y, ext.z});
  const double top = double((1u << kGridBits) - 1);
  const double scale = side > 0.0 ? top / side : 0.0;
  std::vector<Keyed> items(boxes.size());
  auto code = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const dvec3 t = glm::clamp(((boxes[i].lo + boxes[i].hi) - bounds.lo) * scale, 0.0, top);
      items[i] = {std::uint32_t(morton_interleave(std::uint64_t(t.z), std::uint64_t(t.y), std::uint64_t(t.x))),
                  std::uint32_t(i)};
    }
  };
  parallel_chunks(boxes.size(), parts, threads,
                  [&](std::size_t, std::size_t begin, std::size_t end) { code(begin, end); });
  radix_sort(items, threads);  // stable: ties stay in id order
  return items;
}

// The split of sorted items [begin, end): the first item with the highest differing bit set, or
// the middle when all codes are equal.
std::uint32_t split_node(const std::vector<Keyed>& items, std::uint32_t begin, std::uint32_t end) {
  const std::uint32_t diff = items[begin].code ^ items[end - 1].code;
  if (diff == 0) return begin + (end - begin) / 2;
  const std::uint32_t bit = std::uint32_t(1) << (31 - __builtin_clz(diff));
  const auto it = std::partition_point(items.begin() + begin, items.begin() + end,
                                       [bit](const Keyed& k) { return (k.code & bit) == 0; });
  return static_cast<std::uint32_t>(it - items.begin());
}

// Children are created after their parent, so one backward sweep sets every box bottom-up.
// \pre the leaf boxes of the nodes' items are in place.
void fit_boxes(std::vector<BvhNode>& nodes, const std::vector<Aabb>& leaf_boxes) {
  for (std::size_t k = nodes.size(); k-- > 0;) {
    BvhNode& node = nodes[k];
    node.box = Aabb{};
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) node.box.expand(leaf_boxes[i]);
    } else {
      node.box.expand(nodes[node.first].box);
      node.box.expand(nodes[node.first + 1].box);
    }
  }
}

// The nodes of the subtree over refs[begin, end), root first; inner nodes' `first` indexes
// this vector, leaves' `first` indexes refs.
std::vector<BvhNode> build_nodes(const std::vector<Keyed>& refs, std::uint32_t begin, std::uint32_t end, std::uint32_t leaf) {
  std::vector<BvhNode> nodes(1);
  nodes.reserve(2 * ((end - begin) / leaf + 1));
  std::vector<BuildTask> stack{{0, begin, end}};
  while (!stack.empty()) {
    const BuildTask task = stack.back();
    stack.pop_back();
    if (task.end - task.begin <= leaf) {
      nodes[task.node].first = task.begin;
      nodes[task.node].count = task.end - task.begin;
      continue;
    }
    const std::uint32_t mid = split_node(refs, task.begin, task.end);
    const auto left = static_cast<std::uint32_t>(nodes.size());
    nodes[task.node].first = left;
    nodes[task.node].count = 0;
    nodes.emplace_back();
    nodes.emplace_back();
    stack.push_back({left + 1, mid, task.end});
    stack.push_back({left, task.begin, mid});
  }
  return nodes;
}

// The root over two subtrees built by build_nodes: children must be adjacent, so the two
// subtree roots go to 1 and 2, then the rest of the left subtree, then the rest of the right.
std::vector<BvhNode> join_subtrees(const std::vector<BvhNode>& left, const std::vector<BvhNode>& right) {
  const auto nl = static_cast<std::uint32_t>(left.size());
  auto left_index = [](std::uint32_t k) { return k == 0 ? 1u : k + 2u; };
  auto right_index = [nl](std::uint32_t k) { return k == 0 ? 2u : k + 1u + nl; };
  std::vector<BvhNode> nodes(1 + left.size() + right.size());
  nodes[0] = {Aabb{}, 1, 0};
  for (std::uint32_t k = 0; k < left.size(); ++k) {
    BvhNode node = left[k];
    if (node.count == 0) node.first = left_index(node.first);
    nodes[left_index(k)] = node;
  }
  for (std::uint32_t k = 0; k < right.size(); ++k) {
    BvhNode node = right[k];
    if (node.count == 0) node.first = right_index(node.first);
    nodes[right_index(k)] = node;
  }
  return nodes;
}

// The fitted subtree over refs[begin, end), its items and leaf boxes written into `bvh` (whose
// items and leaf_boxes are sized for all refs).
std::vector<BvhNode> build_subtree(const std::vector<Keyed>& refs, const std::vector<Aabb>& boxes, std::uint32_t begin,
                                   std::uint32_t end, std::uint32_t leaf, Bvh& bvh) {
  // A gather at random (the boxes in Morton order): prefetched a few items ahead so the loads
  // overlap instead of stalling one by one.
  constexpr std::uint32_t kAhead = 16;
  for (std::uint32_t k = begin; k < end; ++k) {
    if (k + kAhead < end) __builtin_prefetch(&boxes[refs[k + kAhead].id]);
    bvh.items[k] = refs[k].id, bvh.leaf_boxes[k] = boxes[refs[k].id];
  }
  std::vector<BvhNode> nodes = build_nodes(refs, begin, end, leaf);
  fit_boxes(nodes, bvh.leaf_boxes);
  return nodes;
}

double box_distance2(const Aabb& box, const dvec3& p) {
  const dvec3 d = glm::max(glm::max(box.lo - p, p - box.hi), dvec3(0.0));
  return glm::dot(d, d);
}

ClosestPoint closest_on_segment(const dvec3& p, const dvec3& a, const dvec3& b, int ia, int ib) {
  const dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  double s = len2 > 0.0 ? glm::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  ClosestPoint c;
  c.point = a + s * ab;
  c.barycentric[ia] = 1.0 - s;
  c.barycentric[ib] = s;
  c.squared_distance = glm::dot(p - c.point, p - c.point);
  return c;
}

ClosestPoint result(const dvec3& p, const dvec3& point, const dvec3& bary) {
  ClosestPoint c;
  c.point = point;
  c.barycentric = bary;
  c.squared_distance = glm::dot(p - point, p - point);
  return c;
}

}  // namespace

// Ericson, Real-Time Collision Detection, 5.1.5.
ClosestPoint closest_point_on_triangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) {
  const dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return result(p, a, {1, 0, 0});
  const dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return result(p, b, {0, 1, 0});
  const dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return result(p, c, {0, 0, 1});
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  const double sum = va + vb + vc;
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    ClosestPoint best = closest_on_segment(p, a, b, 0, 1);
    for (const ClosestPoint& e : {closest_on_segment(p, b, c, 1, 2), closest_on_segment(p, c, a, 2, 0)})
      if (e.squared_distance < best.squared_distance) best = e;
    return best;
  }
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return result(p, a + v * ab, {1 - v, v, 0});
  }
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return result(p, a + w * ac, {1 - w, 0, w});
  }
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return result(p, b + w * (c - b), {0, 1 - w, w});
  }
  const double v = vb / sum, w = vc / sum;
  return result(p, a + ab * v + ac * w, {1 - v - w, v, w});
}

std::vector<Aabb> triangle_boxes(const std::vector<dvec3>& positions,
                                 const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads) {
  std::vector<Aabb> boxes(triangles.size());
  const std::size_t chunks = threads >= 2 && boxes.size() >= kParallelItems ? chunk_count(boxes.size(), 4096) : 1;
  parallel_chunks(boxes.size(), chunks, threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
      for (std::uint32_t v : triangles[t]) boxes[t].expand(positions[v]);
  });
  return boxes;
}

namespace {

void fill_float_boxes(Bvh& bvh, int threads) {
  const std::size_t n = bvh.leaf_boxes.size(), padded = n + FloatLeafBoxes::kLanes;
  for (int a = 0; a < 3; ++a) {
    bvh.float_boxes.lo[a].assign(padded, std::numeric_limits<float>::infinity());
    bvh.float_boxes.hi[a].assign(padded, -std::numeric_limits<float>::infinity());
  }
  const std::size_t chunks = threads >= 2 && n >= kParallelItems ? chunk_count(n, 4096) : 1;
  parallel_chunks(n, chunks, threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      for (int a = 0; a < 3; ++a) {
        bvh.float_boxes.lo[a][k] = float_below(bvh.leaf_boxes[k].lo[a]);
        bvh.float_boxes.hi[a][k] = float_above(bvh.leaf_boxes[k].hi[a]);
      }
  });
}

}  // namespace

Bvh build_bvh(const std::vector<Aabb>& boxes, const BvhOptions& options) {
  Bvh bvh;
  const auto n = static_cast<std::uint32_t>(boxes.size());
  if (n == 0) return bvh;
  const std::uint32_t leaf = std::max<std::uint32_t>(1, options.leaf_size);
  const std::vector<Keyed> refs = morton_sorted(boxes, options.threads);
  bvh.items.resize(n);
  bvh.leaf_boxes.resize(n);
  if (options.threads < 2 || n < kParallelItems || n <= leaf) {
    bvh.nodes = build_subtree(refs, boxes, 0, n, leaf, bvh);
  } else {
    // The two halves of the root touch disjoint ranges of refs: build them side by side and
    // append them behind the root (the same tree as the serial build).
    const std::uint32_t mid = split_node(refs, 0, n);
    std::vector<BvhNode> left, right;
    parallel_pair([&] { left = build_subtree(refs, boxes, 0, mid, leaf, bvh); },
                  [&] { right = build_subtree(refs, boxes, mid, n, leaf, bvh); });
    bvh.nodes = join_subtrees(left, right);
    bvh.nodes[0].box = bvh.nodes[1].box;
    bvh.nodes[0].box.expand(bvh.nodes[2].box);
  }
  fill_float_boxes(bvh, options.threads);
  return bvh;
}

std::vector<std::uint32_t> number_items_in_leaf_order(Bvh& bvh) {
  std::vector<std::uint32_t> old = bvh.items;
  for (std::uint32_t k = 0; k < bvh.items.size(); ++k) bvh.items[k] = k;
  return old;
}

Bvh build_bvh(const std::vector<dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
              const BvhOptions& options) {
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (!std::isfinite(positions[v].x) || !std::isfinite(positions[v].y) || !std::isfinite(positions[v].z))
      throw InputError("vertex " + std::to_string(v) + ": coordinate is not finite");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::uint32_t v : triangles[t])
      if (v >= positions.size())
        throw InputError("triangle " + std::to_string(t) + ": vertex index " + std::to_string(v) +
                         " out of range (" + std::to_string(positions.size()) + " vertices)");
  Bvh bvh = build_bvh(triangle_boxes(positions, triangles, options.threads), options);
  bvh.positions = positions;
  bvh.triangles = triangles;
  return bvh;
}

namespace {

struct Nowhere {
  bool operator()(const Aabb&) const { return false; }
};

// Calls hit(item) for the items whose boxes overlap `box` (less those in boxes `outside` holds
// for), in leaf order, until it returns true; returns whether one did.
template <class Hit, class Outside = Nowhere>
bool each_box(const Bvh& bvh, const Aabb& box, const Hit& hit, const Outside& outside = {}) {
  if (bvh.nodes.empty()) return false;
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    if (!node.box.overlaps(box) || outside(node.box)) continue;
    if (node.count > 0) {
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
        if (bvh.leaf_boxes[k].overlaps(box) && !outside(bvh.leaf_boxes[k]) && hit(bvh.items[k])) return true;
      continue;
    }
    stack[top++] = node.first + 1;
    stack[top++] = node.first;
  }
  return false;
}

}  // namespace

void query_box(const Bvh& bvh, const Aabb& box, std::vector<std::uint32_t>& out) {
  each_box(bvh, box, [&](std::uint32_t item) {
    out.push_back(item);
    return false;
  });
}

void query_box_where(const Bvh& bvh, const Aabb& box, const std::function<bool(const Aabb&)>& outside,
                     std::vector<std::uint32_t>& out) {
  each_box(
      bvh, box,
      [&](std::uint32_t item) {
        out.push_back(item);
        return false;
      },
      outside);
}

bool any_box(const Bvh& bvh, const Aabb& box) {
  return each_box(bvh, box, [](std::uint32_t) { return true; });
}

ClosestPoint closest_point(const Bvh& bvh, const dvec3& query) {
  return closest_point(bvh, query, std::numeric_limits<double>::infinity());
}

// A triangle replaces the best so far only when strictly nearer, and the traversal order does not
// depend on the bound: a bound above the answer only skips subtrees that hold nothing as near, so
// the first triangle met at the least distance is the same as without it.
ClosestPoint closest_point(const Bvh& bvh, const dvec3& query, double bound) {
  ClosestPoint best;
  if (bvh.nodes.empty() || bvh.triangles.empty()) return best;
  best.squared_distance = bound;
  bool found = false;
  struct Entry {
    std::uint32_t node;
    double d2;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {0, box_distance2(bvh.nodes[0].box, query)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 >= best.squared_distance) continue;
    const BvhNode& node = bvh.nodes[e.node];
    if (node.count > 0) {
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
        const std::uint32_t t = bvh.items[k];
        const auto& tri = bvh.triangles[t];
        ClosestPoint c = closest_point_on_triangle(query, bvh.positions[tri[0]], bvh.positions[tri[1]], bvh.positions[tri[2]]);
        if (c.squared_distance < best.squared_distance) {
          c.triangle = t;
          best = c;
          found = true;
        }
      }
      continue;
    }
    const Entry l{node.first, box_distance2(bvh.nodes[node.first].box, query)};
    const Entry r{node.first + 1, box_distance2(bvh.nodes[node.first + 1].box, query)};
    // Nearer child on top of the stack, so it is searched first and prunes the other.
    if (l.d2 <= r.d2) {
      stack[top++] = r;
      stack[top++] = l;
    } else {
      stack[top++] = l;
      stack[top++] = r;
    }
  }
  if (!found) best.squared_distance = std::numeric_limits<double>::infinity();
  return best;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> overlapping_pairs(const Bvh& a, const Bvh& b, int threads) {
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  auto out = collect_overlaps<Pair>(a, b, false, threads,
                                    [](std::uint32_t i, std::uint32_t j, std::vector<Pair>& o) { o.emplace_back(i, j); });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> self_overlapping_pairs(const Bvh& bvh, int threads) {
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  auto out = collect_overlaps<Pair>(bvh, bvh, true, threads,
                                    [](std::uint32_t i, std::uint32_t j, std::vector<Pair>& o) { o.emplace_back(i, j); });
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fracref
