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

#include "rim/cut_triangulation.hpp"
#include "rim/exterior_mesh.hpp"

namespace fracref::pieces_detail {

using rim::ExteriorMesh;
using rim::format_point;
using rim::kNone;
using rim::Location;
using rim::location_sides;
using rim::side_uv;

using rim::CutTriangle;
using rim::triangulate_cut_triangle;

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
