#pragma once
// Small procedural triangle meshes (flat arrays) for tests, demos and benchmarks.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// A triangle mesh on flat arrays.
struct TriangleSoup {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// A regular grid sheet: (nx+1) x (ny+1) vertices at origin + i/nx * ex + j/ny * ey, each cell
/// split into two triangles along the same diagonal. Open; front side faces ex x ey.
/// \pre nx, ny >= 1.
TriangleSoup make_grid_sheet(const glm::dvec3& origin, const glm::dvec3& ex, const glm::dvec3& ey, int nx, int ny);

/// The surface of the box [lo, hi], each face an n x n grid: closed, manifold, outward
/// (counterclockwise seen from outside), coplanar neighbours on every face. \pre n >= 1.
TriangleSoup make_box(const glm::dvec3& lo, const glm::dvec3& hi, int n);

/// A UV sphere with `rings` latitude bands (>= 2) and `segments` longitudes (>= 3): closed,
/// manifold, outward, poles shared by their fans.
TriangleSoup make_uv_sphere(const glm::dvec3& centre, double radius, int rings, int segments);

}  // namespace fracref
