#include "field/strength.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geom/bvh.hpp"
#include "util/parallel.hpp"

namespace fracref {

namespace {

constexpr unsigned kBlock = 4;  // nodes a side of the blocks that share one candidate list

double box_distance2(const Aabb& box, const glm::dvec3& p) {
  const glm::dvec3 d = glm::max(glm::max(box.lo - p, p - box.hi), glm::dvec3(0.0));
  return glm::dot(d, d);
}

struct Near {
  double distance;     // of the triangle's box from the block's centre
  std::uint32_t slot;  // the triangle's leaf slot
  bool operator<(const Near& o) const { return distance < o.distance || (distance == o.distance && slot < o.slot); }
};

// The triangles whose boxes come within squared distance r2 of c, nearest box first.
void triangles_near(const Bvh& bvh, const glm::dvec3& c, double r2, std::vector<Near>& out) {
  out.clear();
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    if (box_distance2(node.box, c) > r2) continue;
    if (node.count == 0) {
      stack[top++] = node.first, stack[top++] = node.first + 1;
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
      if (const double d2 = box_distance2(bvh.leaf_boxes[k], c); d2 <= r2) out.push_back({std::sqrt(d2), k});
  }
  std::sort(out.begin(), out.end());
}

struct Block {
  glm::uvec3 lo, hi;  // node range, hi exclusive
};

// Distances of one block's nodes. The triangle nearest to node p is within d(c) + |p − c| of p,
// so within d(c) + 2 max|p − c| of the block's centre c: the nodes search only the triangles
// whose boxes are that near c (slack for rounding), each skipped when its box is farther than
// the best so far. The minimum is over the same squared distances as closest_point's, so the
// values are those of one query per node.
void block_distances(const Grid3& grid, const Bvh& bvh, const Block& b, std::vector<Near>& near, Grid3& out) {
  const glm::dvec3 first = grid.node_position(b.lo.x, b.lo.y, b.lo.z);
  const glm::dvec3 c = 0.5 * (first + grid.node_position(b.hi.x - 1, b.hi.y - 1, b.hi.z - 1));
  const double radius = 0.5 * grid.cell * glm::length(glm::dvec3(b.hi - b.lo - 1u));
  const double reach = (std::sqrt(closest_point(bvh, c).squared_distance) + 2.0 * radius) * (1.0 + 1e-9) + 1e-12;
  triangles_near(bvh, c, reach * reach, near);
  for (unsigned z = b.lo.z; z < b.hi.z; ++z)
    for (unsigned y = b.lo.y; y < b.hi.y; ++y)
      for (unsigned x = b.lo.x; x < b.hi.x; ++x) {
        const glm::dvec3 p = grid.node_position(x, y, z);
        const double off = glm::distance(p, c) * (1.0 + 1e-9) + 1e-12;
        double best = std::numeric_limits<double>::infinity();
        for (const auto& [from_c, k] : near) {
          // Every later box is at least from_c − |p − c| from p: none can beat the best.
          if (from_c - off > 0.0 && (from_c - off) * (from_c - off) > best * (1.0 + 1e-9)) break;
          if (box_distance2(bvh.leaf_boxes[k], p) >= best) continue;
          const auto& t = bvh.triangles[bvh.items[k]];
          const auto& x = bvh.positions;
          best = std::min(best, closest_point_on_triangle(p, x[t[0]], x[t[1]], x[t[2]]).squared_distance);
        }
        out.values[grid.index(x, y, z)] = float(std::sqrt(best));
      }
}

}  // namespace

Grid3 distance_grid(const Grid3& grid, const std::vector<glm::dvec3>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads) {
  Bvh bvh = build_bvh(positions, triangles);
  Grid3 out = grid;
  out.values.assign(grid.size(), 0.0f);
  const glm::uvec3 n = (grid.dims + (kBlock - 1)) / kBlock;
  const std::size_t blocks = std::size_t(n.x) * n.y * n.z;
  parallel_chunks(blocks, chunk_count(blocks, 8), threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::vector<Near> near;
    for (std::size_t k = begin; k < end; ++k) {
      const glm::uvec3 at(unsigned(k % n.x), unsigned(k / n.x % n.y), unsigned(k / (std::size_t(n.x) * n.y)));
      block_distances(grid, bvh, {at * kBlock, glm::min(at * kBlock + kBlock, grid.dims)}, near, out);
    }
  });
  return out;
}

Grid3 modified_field(const Grid3& zeta, const Grid3& distance, const FieldWeights& w, double diagonal) {
  Grid3 psi = zeta;
  for (std::size_t i = 0; i < psi.values.size(); ++i)
    psi.values[i] = float(w.strength * zeta.values[i] + w.distance * distance.values[i] / diagonal + w.offset);
  return psi;
}

}  // namespace fracref
