#include "io/polygon_triangulation.hpp"

#include <cmath>

#include "geom/predicates.hpp"

namespace fracref {
namespace {

int dominant_axis(const std::vector<glm::dvec3>& p, const std::uint32_t* v, std::size_t n, double& sign) {
  glm::dvec3 normal(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = p[v[i]], b = p[v[(i + 1) % n]];
    normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  const glm::dvec3 m = glm::abs(normal);
  const int axis = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
  // orient2d_projected keeps the two other axes in increasing order: (y, z), (x, z) or (x, y).
  // Seen from +axis that is counterclockwise for x and z dropped, clockwise for y dropped.
  sign = (normal[axis] >= 0.0 ? 1.0 : -1.0) * (axis == 1 ? -1.0 : 1.0);
  return axis;
}

// Whether corner `at` of the remaining polygon `ring` is an ear.
bool is_ear(const std::vector<glm::dvec3>& p, const std::vector<std::uint32_t>& ring, std::size_t at, int axis,
            int sign) {
  const std::size_t n = ring.size();
  const glm::dvec3 a = p[ring[(at + n - 1) % n]], b = p[ring[at]], c = p[ring[(at + 1) % n]];
  if (orient2d_projected(a, b, c, axis) != sign) return false;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == at || k == (at + 1) % n || k == (at + n - 1) % n) continue;
    const glm::dvec3 q = p[ring[k]];
    if (q == a || q == b || q == c) continue;
    // Inside or on the boundary of the ear's triangle: clipping it would cut that corner off.
    if (orient2d_projected(a, b, q, axis) != -sign && orient2d_projected(b, c, q, axis) != -sign &&
        orient2d_projected(c, a, q, axis) != -sign)
      return false;
  }
  return true;
}

}  // namespace

void triangulate_polygon(const std::vector<glm::dvec3>& positions, const std::uint32_t* v, std::size_t n,
                         std::vector<std::array<std::uint32_t, 3>>& out) {
  double normal_sign = 1.0;
  const int axis = dominant_axis(positions, v, n, normal_sign);
  const int sign = normal_sign > 0.0 ? 1 : -1;
  std::vector<std::uint32_t> ring(v, v + n);
  while (ring.size() > 3) {
    // From corner 1 on: a convex polygon gives the fan from its first corner, as before.
    const std::size_t m = ring.size();
    std::size_t k = 0;
    while (k < m && !is_ear(positions, ring, (k + 1) % m, axis, sign)) ++k;
    if (k == m) break;
    const std::size_t at = (k + 1) % m;
    out.push_back({ring[(at + m - 1) % m], ring[at], ring[(at + 1) % m]});
    ring.erase(ring.begin() + std::ptrdiff_t(at));
  }
  for (std::size_t i = 1; i + 1 < ring.size(); ++i) out.push_back({ring[0], ring[i], ring[i + 1]});
}

}  // namespace fracref
