#pragma once
// Diagonal slabs: a box's complement for the collision broad phase. Bounds along eight directions
// diagonal to the axes, in single precision rounded outward, tested eight at a time.
#include <cstdint>

#include <glm/glm.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fracref {

/// The directions of Slabs: the six face diagonals (±1 on two axes) and two of the four body
/// diagonals. Pairs whose axis-aligned boxes overlap on a surface are mostly neighbours that a
/// diagonal direction separates; these eight separate most of them, and the other two body
/// diagonals add little for their cost.
inline constexpr int kSlabCount = 8;
inline constexpr int kSlabDirections[kSlabCount][3] = {{1, 1, 0},  {1, -1, 0}, {1, 0, 1},  {1, 0, -1},
                                                       {0, 1, 1},  {0, 1, -1}, {1, -1, 1}, {-1, 1, 1}};

/// The interval [lo[k], hi[k]] of n_k . x over a point set, n_k = kSlabDirections[k]. The default
/// is empty (every lo > hi): the neutral element of merge.
struct alignas(16) Slabs {
  float lo[kSlabCount] = {1e38f, 1e38f, 1e38f, 1e38f, 1e38f, 1e38f, 1e38f, 1e38f};
  float hi[kSlabCount] = {-1e38f, -1e38f, -1e38f, -1e38f, -1e38f, -1e38f, -1e38f, -1e38f};
};

/// The slabs of the segment from a to b (a point's path over a step), each interval widened by
/// pad * |n_k| on both sides and rounded outward to float, past the rounding of the projections:
/// two sets whose padded slabs are apart along some direction are more than 2 * pad apart
/// (Euclidean) everywhere.
/// \pre finite a, b, pad >= 0, |coordinates| < 1e37.
Slabs segment_slabs(const glm::dvec3& a, const glm::dvec3& b, double pad);

/// The slabs of n points (their convex hull), widened and rounded as segment_slabs.
/// \pre as segment_slabs, n >= 1.
Slabs point_slabs(const glm::dvec3* points, int n, double pad);

/// Widens `into` to hold `other` too.
inline void merge(Slabs& into, const Slabs& other) {
  for (int k = 0; k < kSlabCount; ++k) {
    into.lo[k] = other.lo[k] < into.lo[k] ? other.lo[k] : into.lo[k];
    into.hi[k] = other.hi[k] > into.hi[k] ? other.hi[k] : into.hi[k];
  }
}

/// Whether the intervals of a and b are disjoint along some direction (closed intervals: slabs
/// that touch are not apart).
inline bool slabs_apart(const Slabs& a, const Slabs& b) {
#if defined(__SSE2__)
  const __m128 low = _mm_or_ps(_mm_cmplt_ps(_mm_load_ps(a.hi), _mm_load_ps(b.lo)),
                               _mm_cmplt_ps(_mm_load_ps(b.hi), _mm_load_ps(a.lo)));
  const __m128 high = _mm_or_ps(_mm_cmplt_ps(_mm_load_ps(a.hi + 4), _mm_load_ps(b.lo + 4)),
                                _mm_cmplt_ps(_mm_load_ps(b.hi + 4), _mm_load_ps(a.lo + 4)));
  return _mm_movemask_ps(_mm_or_ps(low, high)) != 0;
#else
  bool apart = false;
  for (int k = 0; k < kSlabCount; ++k) apart = apart || a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k];
  return apart;
#endif
}

}  // namespace fracref
