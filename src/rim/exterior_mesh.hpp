#pragma once
// The exterior B as the rim of S sees it: B's flat adjacency, points located on B (a vertex, a
// point of an edge, a point inside a triangle), and the walk of a path across B between two
// such points. The refiner keeps every rim vertex of S at such a location and every rim edge
// inside one triangle of B (rim/rim_on_b.hpp); the pieces stage cuts B along them.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "io/mesh_soup.hpp"

namespace fracref::rim {

inline constexpr std::uint32_t kNone = 0xffffffffu;

/// B with the adjacency the walk needs. Side k of triangle f runs from corner k to corner k+1.
struct ExteriorMesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<glm::uvec2> edges;                      ///< (a < b), sorted
  std::vector<std::array<std::uint32_t, 2>> edge_faces;  ///< the two faces of each edge
  std::vector<std::array<std::uint32_t, 3>> face_edges;  ///< edge of side k
  std::vector<std::uint32_t> vf_offsets, vf_faces;    ///< vertex -> faces (ascending)
  std::vector<glm::dvec3> face_normals;               ///< unit (zero for a degenerate face)
  Bvh bvh;
  double diagonal = 0.0;
};

/// B's mesh, triangles in the soup's order.
/// \throw InputError when the soup has no triangles, an index out of range, a repeated vertex in
///        a face, a non-finite coordinate, an edge that does not have exactly two faces in
///        opposite directions, or a negative volume (wound inward).
ExteriorMesh make_exterior_mesh(const MeshSoup& soup);

/// The edge id of {a, b}, or kNone.
std::uint32_t find_exterior_edge(const ExteriorMesh& m, std::uint32_t a, std::uint32_t b);

/// A point of B: on a vertex, inside an edge (t along edges[id] from .x to .y, in (0, 1)), or
/// inside a triangle (barycentric weights of its corners, all > 0).
struct Location {
  enum Kind : std::uint8_t { kVertex, kEdge, kFace };
  Kind kind = kVertex;
  std::uint32_t id = 0;
  double t = 0.0;
  glm::dvec3 bary{0.0};
  glm::dvec3 point{0.0};
};

bool same_location(const Location& a, const Location& b);
/// Bit k set when the location lies on side k of triangle f (0 when inside or not on f).
unsigned location_sides(const ExteriorMesh& m, const Location& loc, std::uint32_t f);
/// Whether the location lies in the closed triangle f.
bool location_in_face(const ExteriorMesh& m, const Location& loc, std::uint32_t f);
/// The triangles whose closure holds the location, ascending.
std::vector<std::uint32_t> location_faces(const ExteriorMesh& m, const Location& loc);
/// Unit normal of B at the location (angle-weighted at a vertex, mean of two at an edge).
glm::dvec3 location_normal(const ExteriorMesh& m, const Location& loc);
/// The location of the closest point of B to p, weights below `epsilon` zeroed.
Location locate_on_exterior(const ExteriorMesh& m, const glm::dvec3& p, double epsilon, double* distance);
/// Location on edge e at parameter t (t in (0, 1)), point computed from t.
Location edge_location(const ExteriorMesh& m, std::uint32_t e, double t);
Location vertex_location(const ExteriorMesh& m, std::uint32_t v);

/// The barycentric weights of the location in triangle f (exact zeros off its support).
/// \pre location_in_face(m, loc, f).
glm::dvec3 location_weights(const ExteriorMesh& m, const Location& loc, std::uint32_t f);
/// The location with weights w (non-negative, summing to 1) in triangle f: a vertex where two
/// weights are zero, an edge point where one is, else a point inside f.
Location location_from_weights(const ExteriorMesh& m, std::uint32_t f, const glm::dvec3& w);
/// The lowest triangle whose closure holds both locations, or kNone.
std::uint32_t common_face(const ExteriorMesh& m, const Location& a, const Location& b);
/// The point (1 - t) a + t b of the segment between two locations of one triangle, located
/// (so a point of a segment along a B edge is on that edge). \pre common_face(m, a, b) != kNone.
Location location_between(const ExteriorMesh& m, const Location& a, const Location& b, double t);

/// The barycentric-plane position (corner 0 at (0, 0), 1 at (1, 0), 2 at (0, 1)) of the point at
/// parameter t of the edge on side k of a triangle; `forward` when the side runs from the edge's
/// lower vertex. Points of side 1 get x + y == 1 exactly.
glm::dvec2 side_uv(int k, bool forward, double t);
/// The position of a location in the barycentric plane of triangle f (see side_uv).
/// \pre location_in_face(m, loc, f).
glm::dvec2 location_uv(const ExteriorMesh& m, const Location& loc, std::uint32_t f);

/// The triangle of B that a rim segment between locations a and b runs inside: their common face
/// (common_face), or kNone when they share none or the segment runs along a side of it (both
/// ends on that side: the pieces stage orders such segments among the points on their B edge).
std::uint32_t segment_face(const ExteriorMesh& m, const Location& a, const Location& b);

/// Whether segments a-b and c-d, inside triangle f of B, cross at a point inside both: each
/// pair's ends strictly on either side of the other's line (exact orient2d in f's barycentric
/// plane). Segments that share an end or only touch do not cross; the pieces stage cannot cut f
/// along two that do ("two traced paths cross").
/// \pre every location lies in f (location_in_face).
bool segments_cross_in_face(const ExteriorMesh& m, std::uint32_t f, const Location& a, const Location& b,
                            const Location& c, const Location& d);

/// One segment of a trace: from the previous location to `to`, inside (the closure of) `face`.
struct TraceStep {
  Location to;
  std::uint32_t face = 0;
};

/// A path on B: the start location and the steps to the end.
struct Trace {
  Location from;
  std::vector<TraceStep> steps;
};

/// Walks from p to q across B along the curve where B meets a plane through p and q that holds
/// B's mean normal at p and q (at right angles to B there: the straightest path for a short
/// step), then, failing that, the plane holding p's normal, then q's; `first_plane`, when not
/// zero, is tried first. B vertices within plane_tolerance of the plane count as on it, so a
/// trace may run through B vertices and along B edges.
/// \throw RunError with the reason (the caller names the S edge).
Trace trace_on_exterior(const ExteriorMesh& m, const Location& p, const Location& q, double plane_tolerance,
                        const glm::dvec3& first_plane = glm::dvec3(0.0));

/// Walks from p to q across B along the curve where B meets the plane through p and q with
/// normal `plane_normal` only (trace_on_exterior's walk, no other plane). The walk leaves p by
/// the way that heads straightest for q (`branch` 0), or by the next one (`branch` 1: where the
/// curve passes p, the other way along it, which reaches q round the other side of a closed curve).
/// \throw RunError with the reason when that walk does not reach q, or the plane is degenerate.
Trace trace_in_plane(const ExteriorMesh& m, const Location& p, const Location& q, double plane_tolerance,
                     const glm::dvec3& plane_normal, int branch = 0);

/// Whether the triangle `corners` meets B other than at its own rim points (the contact rule of
/// refine/exterior_contact.hpp, exact): a B triangle that holds none of `rim` must not meet it
/// (triangles_intersect); one that holds some must have every corner without a location strictly
/// on B's inner side of its plane (orient3d); with `holders` false, those are not judged. rim[k]
/// is corner k's location on B, or null.
/// \pre a corner with a location lies at its point.
bool meets_exterior_off_rim(const ExteriorMesh& m, const std::array<glm::dvec3, 3>& corners,
                            const std::array<const Location*, 3>& rim, bool holders = true);

/// "(x, y, z)" with 9 significant digits, for messages.
std::string format_point(const glm::dvec3& p);

}  // namespace fracref::rim
