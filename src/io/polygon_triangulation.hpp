#pragma once
// Triangulation of one planar polygon of a mesh file in its own plane (ear clipping), so that a
// non-convex face is not fanned into triangles that leave it or fold over each other.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// Appends n - 2 triangles covering polygon v[0..n) (indices into `positions`, in the file's
/// winding) to `out`, each wound like the polygon. The polygon is projected onto the coordinate
/// plane its Newell normal is most perpendicular to, and ears are clipped with exact orientation
/// tests (an ear: a convex corner whose triangle holds no other corner of what is left), the
/// first ear from the second corner on, so the result depends only on the input and a convex
/// polygon gives the fan (v0, vi, vi+1). A polygon left with no ear
/// (self-intersecting, or degenerate: all corners on a line) is fanned from its first remaining
/// corner, as a plain reader would.
/// \pre n >= 3; every v[i] < positions.size(); positions finite.
void triangulate_polygon(const std::vector<glm::dvec3>& positions, const std::uint32_t* v, std::size_t n,
                         std::vector<std::array<std::uint32_t, 3>>& out);

}  // namespace fracref
