// point_in_mesh and winding_number of bvh.hpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "geom/predicates.hpp"

namespace fracref {
namespace {

using glm::dvec3;

// Fixed, generic (not axis-aligned, pairwise independent) ray directions.
constexpr double kDirections[8][3] = {
    {0.5413, 0.7981, 0.2647},   {-0.8123, 0.1397, 0.5663},  {0.1919, -0.6037, 0.7738},
    {-0.3571, -0.7229, -0.5917}, {0.9137, -0.2753, -0.2989}, {-0.0661, 0.9313, -0.3581},
    {0.6803, 0.4517, -0.5771},  {-0.7541, -0.3919, 0.5273},
};

enum class Crossing { none, proper, degenerate };

// The segment q + t d, t in [0, 1], with 1 / d per axis (0 where d is 0) taken once per ray.
struct Segment {
  dvec3 q, d, inv;
};

Segment segment(const dvec3& q, const dvec3& d) {
  Segment s{q, d, dvec3(0.0)};
  for (int a = 0; a < 3; ++a)
    if (d[a] != 0.0) s.inv[a] = 1.0 / d[a];
  return s;
}

// Slab test against the box inflated by `margin`, far beyond the rounding of the test itself
// (a product with 1 / d is within an ulp or two of the quotient), so no box the exact segment
// touches is culled.
bool segment_hits_box(const Segment& s, const Aabb& box, double margin) {
  double t0 = 0.0, t1 = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double lo = box.lo[a] - margin, hi = box.hi[a] + margin;
    if (s.d[a] == 0.0) {
      if (s.q[a] < lo || s.q[a] > hi) return false;
      continue;
    }
    double ta = (lo - s.q[a]) * s.inv[a], tb = (hi - s.q[a]) * s.inv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Exact classification of the segment [q, r] against one triangle; r lies outside every face.
Crossing classify(const dvec3& q, const dvec3& r, const Triangle3& t) {
  if (!segment_triangle_intersect(q, r, t)) return Crossing::none;
  const int o1 = orient3d(t[0], t[1], t[2], q), o2 = orient3d(t[0], t[1], t[2], r);
  if (o1 * o2 >= 0) return Crossing::degenerate;
  const int s1 = orient3d(q, r, t[0], t[1]), s2 = orient3d(q, r, t[1], t[2]), s3 = orient3d(q, r, t[2], t[0]);
  const bool clean = (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
  return clean ? Crossing::proper : Crossing::degenerate;
}

Triangle3 corners(const Bvh& bvh, std::uint32_t t) {
  const auto& tri = bvh.triangles[t];
  return {bvh.positions[tri[0]], bvh.positions[tri[1]], bvh.positions[tri[2]]};
}

// Crossing parity along [q, r]: 1 odd, 0 even, -1 when some crossing is degenerate.
// Sets `on_surface` when q lies on a face.
int parity(const Bvh& bvh, const dvec3& q, const dvec3& r, double margin, bool& on_surface) {
  const Segment seg = segment(q, r - q);
  int count = 0;
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const BvhNode& node = bvh.nodes[stack.back()];
    stack.pop_back();
    if (!segment_hits_box(seg, node.box, margin)) continue;
    if (node.count == 0) {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
      const Triangle3 t = corners(bvh, bvh.items[k]);
      if (segment_triangle_intersect(q, q, t)) {
        on_surface = true;
        return 0;
      }
      const Crossing c = classify(q, r, t);
      if (c == Crossing::degenerate) return -1;
      if (c == Crossing::proper) ++count;
    }
  }
  return count & 1;
}

// How far from q along d (a unit direction) the segment leaves the box holding q.
double exit_distance(const Aabb& box, const dvec3& q, const double* d) {
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.0) t = std::min(t, (box.hi[a] - q[a]) / d[a]);
    if (d[a] < 0.0) t = std::min(t, (box.lo[a] - q[a]) / d[a]);
  }
  return t;
}

}  // namespace

bool point_in_mesh(const Bvh& bvh, const dvec3& query) {
  if (bvh.nodes.empty() || bvh.triangles.empty()) return false;
  const Aabb& root = bvh.nodes[0].box;
  if (!root.overlaps(Aabb{query, query})) return false;
  const double scale = glm::length(root.hi - root.lo) + glm::length(query - 0.5 * (root.lo + root.hi));
  const double margin = 1e-9 * scale + 1e-300;
  // Shortest way out of the box first: the segment meets fewer boxes of the tree on its way (a
  // closed mesh gives every non-degenerate direction the same parity, so the order is free).
  std::array<std::pair<double, int>, 8> order;
  for (int k = 0; k < 8; ++k) order[k] = {exit_distance(root, query, kDirections[k]), k};
  std::sort(order.begin(), order.end());
  for (const auto& [exit, k] : order) {
    const auto& dir = kDirections[k];
    // Long enough that r lies outside the (inflated) root box, hence on no face.
    const dvec3 r = query + (2.0 * scale + 1.0) * dvec3(dir[0], dir[1], dir[2]);
    bool on_surface = false;
    const int p = parity(bvh, query, r, margin, on_surface);
    if (on_surface) return true;
    if (p >= 0) return p == 1;
  }
  return winding_number(bvh, query) > 0.5;
}

double winding_number(const Bvh& bvh, const dvec3& query) {
  // Van Oosterom and Strackee's solid angle of each triangle seen from the query.
  double sum = 0.0;
  for (const auto& tri : bvh.triangles) {
    const dvec3 a = bvh.positions[tri[0]] - query, b = bvh.positions[tri[1]] - query, c = bvh.positions[tri[2]] - query;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * std::numbers::pi);
}

}  // namespace fracref
