#include "geom/shapes.hpp"

#include <cmath>
#include <map>
#include <numbers>

namespace fracref {
namespace {

using glm::dvec3;

std::uint32_t index_of(int i, int j, int nx) { return static_cast<std::uint32_t>(j * (nx + 1) + i); }

}  // namespace

TriangleSoup make_grid_sheet(const dvec3& origin, const dvec3& ex, const dvec3& ey, int nx, int ny) {
  TriangleSoup m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.positions.push_back(origin + (double(i) / nx) * ex + (double(j) / ny) * ey);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::uint32_t a = index_of(i, j, nx), b = index_of(i + 1, j, nx);
      const std::uint32_t c = index_of(i + 1, j + 1, nx), d = index_of(i, j + 1, nx);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

TriangleSoup make_box(const dvec3& lo, const dvec3& hi, int n) {
  TriangleSoup m;
  std::map<std::array<int, 3>, std::uint32_t> ids;  // lattice point -> vertex, shared across faces
  auto vertex = [&](const std::array<int, 3>& g) {
    auto [it, fresh] = ids.emplace(g, static_cast<std::uint32_t>(m.positions.size()));
    if (fresh) {
      dvec3 p;
      for (int k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * g[k] / n;
      m.positions.push_back(p);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) right-handed
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<int, 3> g[4];
          const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int k = 0; k < 4; ++k) {
            g[k][axis] = side * n;
            g[k][u] = corner[k][0];
            g[k][v] = corner[k][1];
          }
          std::uint32_t q[4];
          for (int k = 0; k < 4; ++k) q[k] = vertex(g[k]);
          // Counterclockwise about +axis on the high side, about -axis on the low side.
          if (side == 1) {
            m.triangles.push_back({q[0], q[1], q[2]});
            m.triangles.push_back({q[0], q[2], q[3]});
          } else {
            m.triangles.push_back({q[0], q[2], q[1]});
            m.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return m;
}

TriangleSoup make_uv_sphere(const dvec3& centre, double radius, int rings, int segments) {
  TriangleSoup m;
  const double pi = std::numbers::pi;
  m.positions.push_back(centre + dvec3(0, 0, radius));  // north pole
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * pi * s / segments;
      m.positions.push_back(centre + radius * dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                                    std::cos(theta)));
    }
  }
  m.positions.push_back(centre - dvec3(0, 0, radius));  // south pole
  const auto south = static_cast<std::uint32_t>(m.positions.size() - 1);
  auto ring = [&](int r, int s) { return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  for (int s = 0; s < segments; ++s) m.triangles.push_back({south, ring(rings - 1, s + 1), ring(rings - 1, s)});
  return m;
}

}  // namespace fracref
