#pragma once
// S meets B only at its rim (issue 29): a face of S touches a triangle of B only at its own rim
// points located in that triangle. The flow holds back the vertices of a face that a step would
// take across B (refine_rim.cpp, Refiner::hold_exterior_crossings), so that the pieces stage can cut B along the rim in one pass.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "rim/rim_on_b.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// The faces of S (at positions x; a rim vertex at its location's point) that meet B other than
/// at their own rim points, ascending. The rule, exact:
/// - a B triangle that holds none of the face's rim points must not meet the face at all
///   (triangles_intersect);
/// - a B triangle that holds some: every vertex of the face that is not a rim vertex lies
///   strictly inside B's side of the triangle's plane (orient3d), so the face meets that plane
///   only at its rim points.
/// (Two rim vertices of a face whose edge is not a rim edge, a chord, are not judged against each
/// other's triangles: split_rim_chords splits chords.) Only faces with a corner nearer to B
/// than the face's longest edge (by `clearance`, a lower bound of each vertex's distance to B,
/// negative: unknown) are tested; `only`, when given, restricts the test to those faces.
/// \pre s's adjacency current; rim covers s's vertices; x.size() == s.positions.size().
std::vector<std::uint32_t> faces_crossing_exterior(const FractureSurface& s, const std::vector<glm::vec4>& x,
                                                   const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                                                   const std::vector<float>& clearance,
                                                   const std::vector<std::uint32_t>* only = nullptr);

/// faces_crossing_exterior's rule for one face (vertex ids of s, positions x), not yet in s.
bool face_crosses_exterior(const glm::uvec4& face, const std::vector<glm::vec4>& x, const rim::ExteriorMesh& exterior,
                           const rim::RimOnB& rim, const std::vector<float>& clearance);

}  // namespace fracref
