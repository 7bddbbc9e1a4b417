#pragma once
// An axis-aligned bounding-box tree on flat arrays: broad phase for intersection and collision
// tests, closest point on a triangle mesh (boundary projection onto the exterior B), and
// point-in-closed-mesh.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include "util/parallel.hpp"

namespace fracref {

/// A closed axis-aligned box [lo, hi]. The default box is empty (lo > hi).
struct Aabb {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};

  void expand(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void expand(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  /// Closed test: boxes that touch overlap.
  bool overlaps(const Aabb& b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z && b.lo.z <= hi.z;
  }
};

/// One node of the tree. A leaf holds `count` > 0 items: Bvh::items[first .. first+count).
/// An inner node has count == 0 and children `first` and `first + 1`.
struct BvhNode {
  Aabb box;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

/// The leaf boxes again in single precision, rounded outward (each contains its double box), one
/// array per bound and axis in leaf order and padded with kLanes empty boxes: the traversals test
/// a box against a leaf's boxes kLanes at a time this way, then (unless the caller takes the
/// rounded boxes' answers, BoxTest::float_rounded) test those that pass exactly in double, so
/// their answers are those of the double boxes alone.
struct FloatLeafBoxes {
  static constexpr std::uint32_t kLanes = 8;
  std::vector<float> lo[3], hi[3];
};

/// The tree. nodes[0] is the root (no nodes when built from nothing). The triangle overload of
/// build_bvh also keeps the mesh, which closest_point and point_in_mesh read.
struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<std::uint32_t> items;  ///< item ids in leaf order
  std::vector<Aabb> leaf_boxes;      ///< box of items[k] at k (leaf order: a leaf's boxes are contiguous)
  FloatLeafBoxes float_boxes;        ///< leaf_boxes rounded outward to float
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

struct BvhOptions {
  std::uint32_t leaf_size = 4;  ///< most items in a leaf (>= 1)
  int threads = 1;              ///< 2 or more builds the root's two subtrees side by side
};

/// Builds the tree over arbitrary boxes (item id = index in `boxes`): items sorted by the Morton
/// code of their box centre on a cube grid of 1024 cells a side over the centres' bounds (ties by
/// id), each node split where the highest bit differing within its range of codes turns from 0
/// to 1 (a spatial median, longest axis first), at the middle of the range when all codes are
/// equal. Deterministic; the same tree (up to node numbering) for any thread count. O(n) after
/// a radix sort.
/// \pre finite boxes.
Bvh build_bvh(const std::vector<Aabb>& boxes, const BvhOptions& options = {});

/// Renumbers the items in leaf order (items[k] = k afterwards) and returns each one's old id:
/// per-item data gathered in this order is read front to back by a traversal instead of at
/// random (on a large mesh, a cache miss or more per pair).
/// \pre a tree built over boxes (a mesh tree's `triangles` would keep their old numbering).
std::vector<std::uint32_t> number_items_in_leaf_order(Bvh& bvh);

/// The boxes of a mesh's triangles, on up to `threads` threads. \pre indices in range.
std::vector<Aabb> triangle_boxes(const std::vector<glm::dvec3>& positions,
                                 const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads = 1);

/// Builds the tree over the triangles of a mesh (item id = triangle index) and keeps a copy of
/// the mesh. \throw InputError when a triangle has a vertex index out of range or a vertex a
/// non-finite coordinate (names it).
Bvh build_bvh(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
              const BvhOptions& options = {});

/// Appends to `out` the ids of the items whose boxes overlap `box` (closed), in leaf order.
void query_box(const Bvh& bvh, const Aabb& box, std::vector<std::uint32_t>& out);

/// query_box, less the subtrees and items whose box `outside` holds for: a test that must hold
/// for every point of the box it is given (say, that the box lies beyond a plane), so that
/// whatever it skips is away from some other shape. The ids kept are in leaf order still.
void query_box_where(const Bvh& bvh, const Aabb& box, const std::function<bool(const Aabb&)>& outside,
                     std::vector<std::uint32_t>& out);

/// Whether some item's box overlaps `box` (closed): query_box's answer is not empty.
bool any_box(const Bvh& bvh, const Aabb& box);

/// The closest point of a triangle mesh to a query point.
struct ClosestPoint {
  glm::dvec3 point{0.0};
  std::uint32_t triangle = 0;
  glm::dvec3 barycentric{0.0};  ///< weights of the triangle's corners 0, 1, 2 at `point`
  double squared_distance = std::numeric_limits<double>::infinity();
};

/// Closest point of triangle (a, b, c) to p (Ericson's Voronoi-region method; the nearest of
/// the three edges when the triangle has no area). `triangle` is left 0.
ClosestPoint closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                       const glm::dvec3& c);

/// Closest point on the mesh kept by `bvh` (built by the triangle overload) to `query`.
/// Floating-point accurate (not exact); among equally close triangles the traversal order
/// decides, deterministically. \pre the mesh has at least one triangle.
ClosestPoint closest_point(const Bvh& bvh, const glm::dvec3& query);

/// closest_point with a known bound: when the query's squared distance to the mesh is below
/// `bound` the answer is the one closest_point gives (the same triangle and point; subtrees
/// farther than the bound are skipped from the start), otherwise squared_distance is infinite.
ClosestPoint closest_point(const Bvh& bvh, const glm::dvec3& query, double bound);

/// Pairs (i, j) of an item i of `a` and an item j of `b` whose boxes overlap, sorted.
/// Runs on `threads` threads; the result does not depend on their number.
std::vector<std::pair<std::uint32_t, std::uint32_t>> overlapping_pairs(const Bvh& a, const Bvh& b, int threads = default_threads());

/// Pairs (i, j), i < j, of items of one tree whose boxes overlap, sorted.
std::vector<std::pair<std::uint32_t, std::uint32_t>> self_overlapping_pairs(const Bvh& bvh, int threads = default_threads());

/// Whether `query` lies inside the closed mesh kept by `bvh` (points on the surface count as
/// inside). Method: parity of the crossings of a segment from the query to a point far outside
/// the mesh's box, each crossing classified with the exact orient3d. A segment that touches an
/// edge, a vertex or lies in a face's plane across the face is discarded and the next of a fixed
/// list of directions tried (shortest way out of the mesh's box first: the segment meets fewer of
/// the tree's boxes); if all of them are degenerate (practically never), the generalized winding
/// number (sum of solid angles, rounded) decides. Exact for a closed (watertight,
/// consistently connected) mesh whenever a non-degenerate direction exists.
/// \pre the mesh is closed; otherwise the answer is that of some ray's parity.
bool point_in_mesh(const Bvh& bvh, const glm::dvec3& query);

/// Generalized winding number of the mesh kept by `bvh` around `query` (Jacobson et al. 2013):
/// the signed solid angle sum / 4 pi, about 1 inside a closed outward-oriented mesh, 0 outside.
/// O(triangles); not exact.
double winding_number(const Bvh& bvh, const glm::dvec3& query);

}  // namespace fracref
