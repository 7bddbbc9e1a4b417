#pragma once
// Internal to the pieces room: the re-triangulation of B's triangles along S's rim. Not part of
// the public API.
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "rim/exterior_mesh.hpp"

namespace fracref::pieces_detail {

using rim::ExteriorMesh;
using rim::format_point;
using rim::kNone;
using rim::Location;
using rim::location_sides;
using rim::side_uv;

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
/// \throw RunError (the caller names the B triangle) when a constraint passes through another
///        point, two constraints cross, or two points coincide.
std::vector<std::array<std::uint32_t, 3>> triangulate_cut_triangle(const CutTriangle& input);

/// The cut of B: the rim's points on B and its segments. Point ids are the global vertex ids of
/// PieceSet::positions.
struct ExteriorCut {
  std::vector<Location> location;                 ///< per global vertex (meaningful where on_b)
  std::vector<std::uint8_t> on_b;                 ///< per global vertex: it lies on B
  std::vector<std::uint32_t> b_vertex_gid;        ///< per B vertex, its global id (kNone if unused)
  std::map<std::uint32_t, std::vector<std::pair<double, std::uint32_t>>> edge_points;  ///< B edge -> (t, id)
  std::map<std::uint32_t, std::vector<std::uint32_t>> face_points;  ///< B face -> ids strictly inside
  struct Segment {
    std::uint32_t from = 0, to = 0;  ///< global ids (the S rim edge's ends)
    std::uint32_t face = 0;          ///< the B triangle holding it
  };
  std::vector<Segment> segments;
  /// Interior edges of S with both ends on B (global ids, smaller first): the re-triangulation
  /// of B avoids them where it can (a piece would have an edge with four faces).
  std::set<std::pair<std::uint32_t, std::uint32_t>> chords;
};

/// Re-triangulates every B triangle the cut touches (the others keep their corners) and
/// returns all triangles of the cut B on global ids, in B's triangle order.
/// \throw RunError naming the B triangle and the rim edges in it when its cut cannot be
///        triangulated (two rim points coincide, or rim segments cross or overlap).
std::vector<std::array<std::uint32_t, 3>> cut_exterior(const ExteriorMesh& m, ExteriorCut& cut,
                                                       const std::vector<glm::dvec3>& positions, bool delaunay);

}  // namespace fracref::pieces_detail
