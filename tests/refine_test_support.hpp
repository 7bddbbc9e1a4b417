#pragma once
// The refine tests' hand-made case: a unit cube cut by a coarse grid sheet, and fields on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "field/field_sampler.hpp"
#include "field/pyramid.hpp"
#include "io/mesh_soup.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref::test {

/// The vertex of s stored exactly at p (a test failure when there is none).
inline std::uint32_t vertex_at(const FractureSurface& s, const glm::vec3& p) {
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    if (glm::vec3(s.positions[v]) == p) return v;
  ADD_FAILURE() << "no vertex at (" << p.x << ", " << p.y << ", " << p.z << ")";
  return 0;
}

inline MeshSoup unit_cube() {
  MeshSoup m;
  for (int i = 0; i < 8; ++i) m.positions.push_back(glm::dvec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

/// An n×n grid sheet spanning the cube at height height(i, j) over node (i, j), pieces (1 above,
/// 0 below).
template <class Height>
FractureSurface sheet_of(int n, Height height) {
  std::vector<glm::vec4> p;
  std::vector<glm::uvec4> f;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) p.push_back({float(i) / n, float(j) / n, height(i, j), 1.0f});
  auto id = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), 0});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1), 0});
    }
  std::vector<glm::ivec2> pieces(f.size(), glm::ivec2(1, 0));
  return make_fracture_surface(p, f, pieces, 2);
}

/// A grid of n nodes a side from `origin`, `cell` apart, each node's value value(its position).
template <class Value>
Grid3 grid_of(const glm::dvec3& origin, double cell, unsigned n, Value value) {
  Grid3 g;
  g.dims = {n, n, n};
  g.origin = origin;
  g.cell = cell;
  for (unsigned z = 0; z < n; ++z)
    for (unsigned y = 0; y < n; ++y)
      for (unsigned x = 0; x < n; ++x) g.values.push_back(float(value(g.node_position(x, y, z))));
  return g;
}

/// The field ψ = psi(p) on a grid of n nodes a side over the cube [lo, lo + the box's largest
/// side] and a margin of 0.05, with a pyramid of `levels`.
template <class Psi>
FieldGrid4 field_on_box(const glm::dvec3& lo, const glm::dvec3& hi, unsigned n, int levels, Psi psi) {
  const Grid3 g = grid_of(lo - glm::dvec3(0.05), (std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) + 0.1) / double(n - 1), n, psi);
  PyramidOptions po;
  po.levels = levels;
  return precompute_field_gradient(build_pyramid_cpu(g, po));
}

/// field_on_box over the unit cube.
template <class Psi>
FieldGrid4 field_on_cube(unsigned n, int levels, Psi psi) {
  return field_on_box(glm::dvec3(0.0), glm::dvec3(1.0), n, levels, psi);
}

/// A flat sheet at height z.
inline FractureSurface sheet(int n, float z) {
  return sheet_of(n, [z](int, int) { return z; });
}

}  // namespace fracref::test
