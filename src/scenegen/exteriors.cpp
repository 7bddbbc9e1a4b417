// Closed, outward exterior meshes of the analytic demo shapes.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "scenegen/scenegen_internal.hpp"

namespace fracref::scenegen_detail {

TriMesh make_cylinder(double radius, double length, int segments, int rings) {
  TriMesh m;
  const auto ring_vertex = [segments](int k, int j) { return std::uint32_t(k * segments + (j % segments)); };
  for (int k = 0; k <= rings; ++k) {
    const double z = -0.5 * length + length * double(k) / double(rings);
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * std::numbers::pi * double(j) / double(segments);
      m.positions.push_back({radius * std::cos(a), radius * std::sin(a), z});
    }
  }
  const std::uint32_t bottom = std::uint32_t(m.positions.size());
  m.positions.push_back({0.0, 0.0, -0.5 * length});
  m.positions.push_back({0.0, 0.0, 0.5 * length});
  const std::uint32_t top = bottom + 1;
  for (int k = 0; k < rings; ++k)
    for (int j = 0; j < segments; ++j) {
      const std::uint32_t a = ring_vertex(k, j), b = ring_vertex(k, j + 1), c = ring_vertex(k + 1, j + 1),
                          d = ring_vertex(k + 1, j);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  for (int j = 0; j < segments; ++j) {
    m.triangles.push_back({bottom, ring_vertex(0, j + 1), ring_vertex(0, j)});
    m.triangles.push_back({top, ring_vertex(rings, j), ring_vertex(rings, j + 1)});
  }
  return m;
}

namespace {

// Vertices of the box surface grid, shared between faces through their integer coordinates.
class BoxGrid {
 public:
  BoxGrid(const glm::dvec3& lo, const glm::dvec3& hi, const glm::ivec3& cells, double rounding)
      : lo_(lo), hi_(hi), cells_(cells), rounding_(rounding),
        ids_(std::size_t(cells.x + 1) * std::size_t(cells.y + 1) * std::size_t(cells.z + 1), kNone) {}

  std::uint32_t vertex(const glm::ivec3& g) {
    const std::size_t key = std::size_t(g.x) + std::size_t(cells_.x + 1) * (std::size_t(g.y) + std::size_t(cells_.y + 1) * std::size_t(g.z));
    if (ids_[key] == kNone) {
      ids_[key] = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back(place(g));
    }
    return ids_[key];
  }
  TriMesh mesh;

 private:
  glm::dvec3 place(const glm::ivec3& g) const {
    glm::dvec3 p;
    for (int a = 0; a < 3; ++a)
      p[a] = g[a] == cells_[a] ? hi_[a] : lo_[a] + (hi_[a] - lo_[a]) * double(g[a]) / double(cells_[a]);
    return rounding_ > 0.0 ? rounded_box_map(p, lo_, hi_, rounding_) : p;
  }

  static constexpr std::uint32_t kNone = 0xffffffffu;
  glm::dvec3 lo_, hi_;
  glm::ivec3 cells_;
  double rounding_;
  std::vector<std::uint32_t> ids_;
};

}  // namespace

glm::dvec3 rounded_box_map(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi, double radius) {
  const glm::dvec3 inner = glm::clamp(p, lo + radius, hi - radius), d = p - inner;
  const double euclid = glm::length(d), chebyshev = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  return euclid > 0.0 ? inner + d * (chebyshev / euclid) : p;
}

TriMesh make_box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::ivec3& cells, double rounding) {
  BoxGrid grid(lo, hi, cells, rounding);
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
      for (int i = 0; i < cells[u]; ++i)
        for (int j = 0; j < cells[v]; ++j) {
          std::uint32_t q[4];
          const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
          for (int c = 0; c < 4; ++c) {
            glm::ivec3 g(0);
            g[a] = side ? cells[a] : 0;
            g[u] = i + corner[c][0];
            g[v] = j + corner[c][1];
            q[c] = grid.vertex(g);
          }
          if (side) {
            grid.mesh.triangles.push_back({q[0], q[1], q[2]});
            grid.mesh.triangles.push_back({q[0], q[2], q[3]});
          } else {
            grid.mesh.triangles.push_back({q[0], q[2], q[1]});
            grid.mesh.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return std::move(grid.mesh);
}

double mesh_volume(const TriMesh& mesh) {
  double v = 0.0;
  for (const auto& t : mesh.triangles)
    v += glm::dot(mesh.positions[t[0]], glm::cross(mesh.positions[t[1]], mesh.positions[t[2]]));
  return v / 6.0;
}

}  // namespace fracref::scenegen_detail
