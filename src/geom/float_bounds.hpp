#pragma once
// Single-precision bounds of double values, for the float prefilters (the trees' leaf boxes, the
// slabs): a float at most (at least) x, without a branch on the rounding's direction.
#include <cmath>
#include <limits>

namespace fracref {

/// A float <= x: x moved down by 2^-22 of itself (twice the float rounding, at most 2^-24
/// relative) and by 1e-37 (the floats' subnormal range) before it is rounded. The exact
/// rounding's direction goes either way at random, and a mispredicted branch and a library call
/// per bound would be a large share of a tree's build. Beyond the floats' range: the exact
/// rounding down (the largest float for x above it, -inf below). \pre x not NaN.
inline float float_below(double x) {
  if (!(std::abs(x) < 1e38)) {
    const float f = static_cast<float>(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
  }
  return static_cast<float>(x - (std::abs(x) * 0x1p-22 + 1e-37));
}

/// A float >= x, as float_below. \pre x not NaN.
inline float float_above(double x) { return -float_below(-x); }

}  // namespace fracref
