// Slabs of a segment, rounded outward past every rounding on the way.
#include "geom/slabs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fracref {
namespace {

constexpr double kU = 0x1p-53;  // unit roundoff of double

float round_down(double x) {
  float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float round_up(double x) {
  float f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

double project(const int (&n)[3], const glm::dvec3& x) { return (n[0] * x.x + n[1] * x.y) + n[2] * x.z; }

}  // namespace

// A projection is two additions of exact terms (n has entries -1, 0, 1): off by at most
// 2u (|x| + |y| + |z|). 8u of the larger sum also covers the widening subtraction, and
// 1e-12 of the pad its product with |n| (rounded up here: sqrt 2 < 1.4142136, sqrt 3 < 1.7320509).
Slabs segment_slabs(const glm::dvec3& a, const glm::dvec3& b, double pad) {
  const glm::dvec3 m = glm::max(glm::abs(a), glm::abs(b));
  const double rounding = 8.0 * kU * ((m.x + m.y) + m.z);
  Slabs s;
  for (int k = 0; k < kSlabCount; ++k) {
    const int(&n)[3] = kSlabDirections[k];
    const double length = (n[0] != 0 && n[1] != 0 && n[2] != 0) ? 1.7320509 : 1.4142136;
    const double widen = pad * length * (1.0 + 1e-12) + rounding;
    const double pa = project(n, a), pb = project(n, b);
    s.lo[k] = round_down(std::min(pa, pb) - widen);
    s.hi[k] = round_up(std::max(pa, pb) + widen);
  }
  return s;
}

}  // namespace fracref
