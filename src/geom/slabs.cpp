// Slabs of a segment, rounded outward past every rounding on the way.
#include "geom/slabs.hpp"

#include <algorithm>
#include <cmath>

#include "geom/float_bounds.hpp"

namespace fracref {
namespace {

constexpr double kU = 0x1p-53;  // unit roundoff of double

// n . p for the eight directions of kSlabDirections, each as two additions of exact terms, in
// the order ((n_x x + n_y y) + n_z z).
void project(const glm::dvec3& p, double (&out)[kSlabCount]) {
  const double x = p.x, y = p.y, z = p.z;
  out[0] = x + y, out[1] = x - y, out[2] = x + z, out[3] = x - z;
  out[4] = y + z, out[5] = y - z, out[6] = (x - y) + z, out[7] = (y - x) + z;
}

}  // namespace

// A projection is off by at most 2u (|x| + |y| + |z|); 8u of the largest such sum also covers the
// widening subtraction, and 1e-12 of the pad its product with |n| (rounded up here:
// sqrt 2 < 1.4142136, sqrt 3 < 1.7320509).
Slabs point_slabs(const glm::dvec3* points, int n, double pad) {
  glm::dvec3 m = glm::abs(points[0]);
  for (int i = 1; i < n; ++i) m = glm::max(m, glm::abs(points[i]));
  const double rounding = 8.0 * kU * ((m.x + m.y) + m.z);
  const double face = pad * 1.4142136 * (1.0 + 1e-12) + rounding, body = pad * 1.7320509 * (1.0 + 1e-12) + rounding;
  double lo[kSlabCount], hi[kSlabCount], p[kSlabCount];
  project(points[0], lo);
  for (int k = 0; k < kSlabCount; ++k) hi[k] = lo[k];
  for (int i = 1; i < n; ++i) {
    project(points[i], p);
    for (int k = 0; k < kSlabCount; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  Slabs s;
  for (int k = 0; k < kSlabCount; ++k) {
    const double widen = k < 6 ? face : body;
    s.lo[k] = float_below(lo[k] - widen);
    s.hi[k] = float_above(hi[k] + widen);
  }
  return s;
}

Slabs segment_slabs(const glm::dvec3& a, const glm::dvec3& b, double pad) {
  const glm::dvec3 ends[2] = {a, b};
  return point_slabs(ends, 2, pad);
}

}  // namespace fracref
