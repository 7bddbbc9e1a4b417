#pragma once
// Constrained triangulation of one triangle in its barycentric plane (exact orient2d): the
// pieces stage cuts B's triangles along the rim with it, and rim/trim_to_exterior cuts S's faces
// along their intersection with B.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace fracref::rim {

/// Input of the re-triangulation of one B triangle, in its barycentric plane: corner 0 at
/// (0, 0), corner 1 at (1, 0), corner 2 at (0, 1). Points on side 1 satisfy x + y == 1
/// exactly, so collinear points are exactly collinear.
struct CutTriangle {
  std::vector<glm::dvec2> uv;            ///< points 0, 1, 2 are the corners
  std::vector<glm::dvec3> xyz;           ///< 3D positions (shape only)
  std::array<std::vector<std::uint32_t>, 3> side_points;  ///< points strictly inside side k, in order from corner k
  std::vector<std::uint32_t> interior;   ///< points strictly inside
  std::vector<std::pair<std::uint32_t, std::uint32_t>> constraints;  ///< segments that must be edges
  std::vector<std::pair<std::uint32_t, std::uint32_t>> avoid;  ///< free edges to flip away where the quad allows
  bool delaunay = true;
};

/// Triangulates the cut triangle: counterclockwise triangles over the local point ids, every
/// constraint an edge, and no edge of `avoid` that a flip in a strictly convex quad can remove.
/// \throw RunError (the caller names the triangle) when a constraint passes through another
///        point, two constraints cross, or two points coincide.
std::vector<std::array<std::uint32_t, 3>> triangulate_cut_triangle(const CutTriangle& input);

}  // namespace fracref::rim
