#pragma once
// Tet meshes of a closed exterior's inside: the Kuhn lattice and isosurface stuffing (Labelle and
// Shewchuk 2007). Used by the cuts input (cuts_model.cpp) and by the demo scene generator.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// Tets on their vertices, each positively oriented (det[b-a, c-a, d-a] > 0).
struct TetSet {
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec4> tets;
};

/// `cells` cubes over [lo, hi], each split into the 6 tets of the Kuhn triangulation.
struct LatticeSpec {
  glm::dvec3 lo{0.0}, hi{1.0};
  glm::ivec3 cells{1, 1, 1};
};

TetSet box_lattice(const LatticeSpec& spec);
double tet_volume(const TetSet& set, std::uint32_t t);

/// Interior faces (shared by two tets), sorted by their sorted vertex triple: the vertices and
/// the two tets (x < y).
struct InteriorFaces {
  std::vector<glm::uvec3> faces;
  std::vector<glm::uvec2> tets;
};
InteriorFaces interior_faces(const TetSet& set);

/// Keeps the largest face-connected part (ties to the lowest tet), vertices compacted in order.
void keep_largest_part(TetSet& set);

/// The inside of the closed, outward exterior (positions, triangles) as tets whose hull lies on
/// it: the lattice tets cut by the exterior (marching tetrahedra on the inside/outside sign of the
/// lattice vertices), after warping each lattice vertex that has a crossing closer than `warp`
/// times that edge's length onto the nearest one; cut prisms and pyramids are split by vertex
/// ids so the tets conform;
/// largest part only. \pre the lattice box contains the exterior with room.
/// \throw RunError when no tet is inside.
TetSet stuffed_tets(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const LatticeSpec& spec, double warp);

/// stuffed_tets() on a lattice of cubic cells of size h = (the exterior's bounding-box diagonal) /
/// cells_per_diagonal, covering its box with 1.5 cells of room on every side.
/// \pre the exterior is closed and outward; cells_per_diagonal > 0.
/// \throw RunError as stuffed_tets().
TetSet stuff_inside(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    double cells_per_diagonal, double warp);

}  // namespace fracref
