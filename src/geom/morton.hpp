#pragma once
// Morton (Z-order) codes of points in a box, and the permutation that sorts points by them:
// neighbours in the order are mostly neighbours in space, so work done in that order (tree
// queries, vertex renumbering) touches memory that is still in cache.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// Spreads the low 21 bits of v to every third bit.
inline std::uint64_t morton_spread3(std::uint64_t v) {
  v &= 0x1fffffull;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

/// The 63-bit code interleaving the low 21 bits of three grid coordinates, `lowest` in bit 0 of
/// each triple, `highest` in bit 2.
inline std::uint64_t morton_interleave(std::uint64_t lowest, std::uint64_t middle, std::uint64_t highest) {
  return morton_spread3(lowest) | morton_spread3(middle) << 1 | morton_spread3(highest) << 2;
}

/// The 63-bit Morton code of p on a 2^21 grid over [lo, hi] (points outside are clamped).
inline std::uint64_t morton_code(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 size = glm::max(hi - lo, glm::dvec3(1e-300));
  const glm::dvec3 t = glm::clamp((p - lo) / size, 0.0, 1.0) * double((1 << 21) - 1);
  return morton_interleave(std::uint64_t(t.x), std::uint64_t(t.y), std::uint64_t(t.z));
}

/// The permutation that sorts `points` by Morton code over their bounding box (ties by index:
/// deterministic). Non-finite points sort as if clamped.
inline std::vector<std::uint32_t> morton_order(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) keyed[i] = {morton_code(points[i], lo, hi), std::uint32_t(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace fracref
