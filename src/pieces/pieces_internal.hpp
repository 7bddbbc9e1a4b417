#pragma once
// Internal to the pieces room: B's flat adjacency, locations on B, traces, and the two
// re-triangulations. Not part of the public API.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "io/mesh_soup.hpp"
#include "surface/fracture_surface.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {

inline constexpr std::uint32_t kNone = 0xffffffffu;

/// A triangle whose doubled area is below this fraction of its longest edge squared (its height
/// over that edge below this fraction of it) is needle-thin: its normal is noise.
inline constexpr double kNeedle = 0.01;

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

/// \throw InputError (see build_pieces).
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

/// The barycentric-plane position (see CutTriangle) of the point at parameter t of the edge on
/// side k of a triangle; `forward` when the side runs from the edge's lower vertex.
glm::dvec2 side_uv(int k, bool forward, double t);
/// The position of a location in the barycentric plane of triangle f (see CutTriangle), the
/// same coordinates cut_exterior uses. \pre location_in_face(m, loc, f).
glm::dvec2 location_uv(const ExteriorMesh& m, const Location& loc, std::uint32_t f);

/// One segment of a trace: from the previous location to `to`, inside (the closure of) `face`.
struct TraceStep {
  Location to;
  std::uint32_t face = 0;
  /// kNone, or `to` is a route point (see untangle_traces) that keeps this trace clear of the
  /// trace with this index in the EdgeTrace list.
  std::uint32_t clear_of = kNone;
};

/// The trace of one S boundary edge: the start location and the steps to the end.
struct Trace {
  Location from;
  std::vector<TraceStep> steps;
};

/// Walks from p to q across B (see pieces.hpp, step 2).
/// \throw RunError with the reason (the caller names the S edge).
Trace trace_on_exterior(const ExteriorMesh& m, const Location& p, const Location& q, double plane_tolerance,
                        const glm::dvec3& first_plane = glm::dvec3(0.0));

/// The trace of the S boundary edge p -> q, side `side` of S face `s_face` (in its winding).
struct EdgeTrace {
  std::uint32_t s_face = 0;
  int side = 0;
  std::uint32_t p = 0, q = 0;
  Trace trace;
};

/// Two segments of different traces (or of one trace, not neighbours) that cross or touch
/// inside one B triangle (exact orientation tests in its barycentric plane).
struct TraceConflict {
  std::uint32_t face = 0;
  std::uint32_t trace_a = 0, step_a = 0;
  std::uint32_t trace_b = 0, step_b = 0;
};

/// Every pair of conflicting segments, in a deterministic order (by B triangle, then traces).
std::vector<TraceConflict> find_trace_conflicts(const ExteriorMesh& m, const std::vector<EdgeTrace>& traces);

/// Re-routes traces that cross or touch (pieces.hpp, step 2b). Where the boundary of S doubles
/// back on B (a spike, a zigzag of short edges), the trace X of one edge runs a hair from a
/// chain Y of neighbouring traces (the other trace of the conflict and those joined to it at S
/// vertices near X) and, by float noise or the plane cut's bend, passes some of Y's points on
/// the wrong side. The right side is the side of the point of Y (within a tenth of X's chord
/// of X) farthest from X; every point of Y on the wrong side, or nearer to X than an offset
/// eps, gets a route point eps past it on the right side, and X is re-traced through them leg
/// by leg. eps is a quarter of that farthest distance, at most a tenth of the shortest chord
/// involved. One conflict is resolved at a time, the better separated choice of X first.
/// Returns the number of route points added; conflicts it cannot resolve are left for
/// cut_exterior to report.
std::uint32_t untangle_traces(const ExteriorMesh& m, std::vector<EdgeTrace>& traces, double plane_tolerance,
                              double location_epsilon);

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
/// constraint an edge, and no edge of `avoid` that a flip in a strictly convex quad can remove. \throw RunError (the caller names the B triangle) when a constraint
/// passes through another point, two constraints cross, or two points coincide.
std::vector<std::array<std::uint32_t, 3>> triangulate_cut_triangle(const CutTriangle& input);

/// Whether a triangle with all three corners on B lies flat on B (so it may not be made).
using FlatTest = std::function<bool(const glm::dvec3&, const glm::dvec3&, const glm::dvec3&)>;

/// Bit of a fracture polygon's side mask: the point lies on B.
inline constexpr unsigned kOnExterior = 8u;

/// The triangulation of a fracture face's polygon: triangles over polygon indices, where index
/// polygon.size() stands for `centre` when centre_added.
struct FracturePolygon {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  bool centre_added = false;
  glm::dvec3 centre{0.0};
  glm::dvec3 centre_weights{0.0};  ///< of the face's corners, in polygon order: centre = their sum
};

/// Triangulates a fracture face whose sides carry trace points. `polygon` lists 3D points in
/// the face's winding; `side_mask` per point: bit k when it lies on side k (a corner on two),
/// plus kOnExterior when it lies on B. No triangle has all three points on one side (for one
/// cut side this is the fan from the opposite corner), and none with all corners on B for
/// which `flat` holds. When no such triangulation is found (a face with all corners on B whose
/// traces bend over a crease of B), every side is joined to the centroid of the face's corners
/// instead, or, when the centroid does not see every side (a needle-thin face), to the point of
/// a barycentric grid over the corners that sees them best. The polygon is projected along its
/// vector area, which must agree with `normal` (the face's; zero: no check, for a needle-thin
/// face whose own normal is noise); triangles come in the polygon's winding.
/// \throw RunError with the reason (the caller names the S face).
FracturePolygon triangulate_fracture_polygon(const std::vector<glm::dvec3>& polygon, const std::vector<unsigned>& side_mask,
                                             const glm::dvec3& normal, const FlatTest& flat = {});

/// The cut of B: the points the traces put on B and the segments between them. Point ids are
/// the global vertex ids of PieceSet::positions.
struct ExteriorCut {
  std::vector<Location> location;                 ///< per global vertex (meaningful where on_b)
  std::vector<std::uint8_t> on_b;                 ///< per global vertex: it lies on B
  std::vector<std::uint32_t> b_vertex_gid;        ///< per B vertex, its global id (kNone if unused)
  std::map<std::uint32_t, std::vector<std::pair<double, std::uint32_t>>> edge_points;  ///< B edge -> (t, id)
  std::map<std::uint32_t, std::vector<std::uint32_t>> face_points;  ///< B face -> ids strictly inside
  struct Segment {
    std::uint32_t from = 0, to = 0;  ///< global ids
    std::uint32_t face = 0;          ///< the B triangle the walk crossed
    std::uint32_t s_from = 0, s_to = 0;  ///< the S boundary edge it traces
  };
  std::vector<Segment> segments;
  /// Interior edges of S with both ends on B (global ids, smaller first): the re-triangulation
  /// of B avoids them where it can (a piece would have an edge with four faces).
  std::set<std::pair<std::uint32_t, std::uint32_t>> chords;
};

/// Thrown by cut_exterior when the traces of two S boundary edges cross in a B triangle.
struct TracesCross : RunError {
  TracesCross(const std::string& what, std::vector<std::array<glm::uvec2, 2>> crossing)
      : RunError(what), pairs(std::move(crossing)) {}
  std::vector<std::array<glm::uvec2, 2>> pairs;  ///< per B triangle, two S boundary edges (s_from, s_to)
};

/// Re-triangulates every B triangle the cut touches (the others keep their corners) and
/// returns all triangles of the cut B on global ids, in B's triangle order.
/// \throw TracesCross naming the first such B triangle, with a crossing pair of S boundary
///        edges from every B triangle where two traces cross properly (all triangles are cut
///        first); RunError naming the B triangle when its cut cannot be triangulated otherwise.
std::vector<std::array<std::uint32_t, 3>> cut_exterior(const ExteriorMesh& m, ExteriorCut& cut,
                                                       const std::vector<glm::dvec3>& positions, bool delaunay);

struct RepairReport {
  std::uint32_t collapsed = 0;      ///< boundary edges contracted
  std::uint32_t flaps_removed = 0;  ///< faces lying flat on B removed
  std::uint32_t contracted = 0;     ///< edges of `contractions` contracted
  std::vector<std::uint32_t> face_origin;  ///< per face of the result, its face in the input
};

/// S with the edges (gone, keep) of `contractions` contracted into keep, in order (those no
/// longer edges skipped; contractions whose neighbourhoods do not touch an earlier one's are made
/// together, which can let through a pair that one at a time would refuse the second of), then every boundary edge shorter than `min_edge` contracted (shortest first; the end that
/// is kVertexOriginal, else the lower id, is kept) and, when `flaps`, the faces of `left_out`
/// (input numbering: faces with two or three boundary edges whose fracture polygon could not be
/// made) and then every face with two or three boundary edges (so all corners on B) that is
/// needle-thin or whose centroid lies within 0.01 x its longest edge + `tolerance` of B removed.
/// A contraction after which a face moved to the kept end meets another face of S (exact), and
/// an edit that would make S invalid (validate()), are skipped. Vertex ids are kept.
FractureSurface repair_boundary(FractureSurface s, const ExteriorMesh& m, double min_edge, bool flaps,
                                double tolerance, const std::vector<std::uint32_t>& left_out,
                                const std::vector<std::pair<std::uint32_t, std::uint32_t>>& contractions,
                                RepairReport& report);

/// How far, and which way, to push an S vertex into B. A zero direction means along the inward
/// normal of B's triangle nearest to the vertex.
struct Push {
  double distance = 0.0;
  glm::dvec3 direction{0.0};
  double last_depth = 0.0;  // the poke depth that decided the last push (build_pieces' retries)
};

/// The S vertices off B (ids below s_vertex_count with on_b unset) of the triangles with a
/// corner on B whose inside pokes out of B by more than `tolerance` (sampled on a grid), each
/// with how far it alone would have to move to take the deepest such poke back (the poke over
/// its weight there) and which way: from that poke point to its closest point on B. S crosses
/// B there: near its rim where B is concave, or where it hugs B. (The inward normal of B nearest
/// to the vertex can point the wrong way on a thin B: the poke may cross the opposite side.)
std::map<std::uint32_t, Push> poking_vertices(const ExteriorMesh& m, const std::vector<glm::dvec3>& positions,
                                              const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                              const std::vector<std::uint8_t>& on_b, std::uint32_t s_vertex_count,
                                              double tolerance);

/// Moves every rim vertex of S (kVertexBoundary) one of whose inner edges (to a vertex off the
/// rim) leaves it outside B to where that edge enters B (the farthest such point, at most 0.3
/// of the edge along): S overshoots B there and its true rim lies inside. A vertex whose move
/// would make S intersect itself at one of its faces stays. Returns how many moved.
std::uint32_t retract_rim(FractureSurface& s, const ExteriorMesh& m, double tolerance);

/// Moves each vertex of `push` its distance into B, along its direction (see Push). A vertex
/// whose push makes S intersect itself at one of its faces has its push halved until S is clean,
/// and after 6 halvings stays where it was (the poke it leaves is reported later).
void push_inward(FractureSurface& s, const ExteriorMesh& m, const std::map<std::uint32_t, Push>& push);

/// The exact intersections among the fracture triangles (remeshed S faces) and the cut B
/// triangles of an attempt, as vertices a retry can move. At most 256 pairs are looked at.
struct Clashes {
  std::size_t pairs = 0;  ///< intersecting pairs looked at
  /// S vertices off B of fracture triangles that cross B triangles -> the unit inward normal of
  /// those B triangles (their sum, normalised; zero if it cancels out)
  std::map<std::uint32_t, glm::dvec3> poking;
  std::set<std::uint32_t> folded;  ///< S vertices off B of fracture triangles that cross each other
  std::array<std::array<std::uint32_t, 3>, 2> first{};  ///< the first pair, for messages
  std::array<bool, 2> first_is_exterior{};               ///< whether each is a B triangle
};

/// The clashes of `s_triangles` and `b_triangles` (global vertex ids into positions; on_b per
/// vertex, the S vertices are the first s_vertex_count).
Clashes find_clashes(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& s_triangles,
                     const std::vector<std::array<std::uint32_t, 3>>& b_triangles, const std::vector<std::uint8_t>& on_b,
                     std::uint32_t s_vertex_count);

/// Moves each vertex v of `relax` the fraction relax[v] of the way to the centroid of its
/// neighbours in S (unfolding a sharp fold that the rim's traces would make S cross itself at).
/// A vertex whose move would make S intersect itself at one of its faces has its move halved,
/// and after 6 halvings stays. \pre adjacency current.
void relax_toward_neighbours(FractureSurface& s, const std::map<std::uint32_t, double>& relax);

/// "(x, y, z)" with 9 significant digits, for messages.
std::string format_point(const glm::dvec3& p);

}  // namespace fracref::pieces_detail
