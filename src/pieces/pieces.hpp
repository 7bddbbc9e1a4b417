#pragma once
// Watertight high-resolution pieces (paper section 5, "Exterior surface generation";
// docs/DESIGN.md, pipeline step 5): the exterior B is cut along the boundary of the refined fracture
// surface S, split into patches, and every patch is merged with the faces of S that bound the
// same piece, giving one closed, edge-manifold, outward mesh per piece. Neighbouring pieces
// share their fracture vertices exactly (same index in one shared position array).
//
// Method (build_pieces):
//  0. Repair. Boundary edges of S shorter than PieceOptions::merge_tolerance are contracted
//     and faces lying flat on B are left out (see PieceOptions), on a copy of S; a rim vertex
//     one of whose inner edges leaves it outside B (S overshooting a concave B) is moved along
//     that edge to where it enters B.
//  1. Snap. Every boundary vertex of S (kVertexBoundary) is located on B by a closest-point
//     query: a B vertex, a point of a B edge or a point inside a B triangle (barycentric weights
//     below PieceOptions::location_epsilon are zeroed). Its position becomes that point.
//  2. Trace. Each boundary edge (p, q) of S, in the winding of its one face, is traced across
//     B's triangles along the intersection of B with the plane through p and q that contains the
//     mean of B's normals at p and q (the plane is perpendicular to B there, so the curve is the
//     "straightest" path, a discrete geodesic for short edges). The walk goes from triangle to
//     triangle through the crossings of that plane with B's edges; B vertices within
//     plane_epsilon of the plane count as on it, so a trace may run through B vertices and along
//     B edges (an S boundary edge lying on a B edge) without creating slivers. When the walk
//     cannot reach q (a non-convex B folding away from the plane) it is retried with the normal
//     at p alone, then at q alone, before giving up.
// 2b. Untangle. Where the boundary of S doubles back on B (a spike whose two sides run a hair
//     apart, a zigzag of short edges), the trace of one edge can pass points of its neighbours'
//     traces on the wrong side and cross them (by float noise, or because a long edge's plane
//     cut bends away from its chord). Traces that cross or touch are found exactly
//     (orientation tests in each B triangle's barycentric plane). The right side is taken where
//     the neighbouring traces are farthest from the trace (within a tenth of its chord), and
//     the trace is re-traced leg by leg through route points on B a small offset past every
//     neighbouring point it passed on the wrong side or too closely. Repeated until no conflict
//     is left or none can be resolved. Traces that still cross in a B triangle's
//     re-triangulation (step 3) start the build again with the rim vertex the two edges share
//     (a zigzag of the rim) contracted into its nearer neighbour, or with the shorter edge
//     contracted, each contraction tried once.
//  3. Insert. The crossings become new vertices shared by B and S: each cut B triangle is
//     re-triangulated in its own barycentric plane (a constrained triangulation, exact
//     orientation tests, Delaunay flips for shape), and each face of S on a traced edge becomes
//     a polygon re-triangulated by ear clipping (never a triangle lying along B: for one cut edge
//     this is the fan from the opposite corner; a face with all corners on B whose trace bends
//     over a crease of B is fanned from its centroid, see FaceCentre). The polygon must keep
//     the face's orientation (not judged for a needle-thin face, whose normal is noise). A face
//     with two or three boundary edges whose polygon cannot be triangulated (its traces wind
//     around its chord over bumps of B) is left out like a flap, and one with one boundary edge
//     has that edge re-traced in the plane through it along the face's normal (the fan then sees
//     the trace where it sees the edge); either way the build starts again.
// 3b. Push. Where S crosses B near its rim (it hugs B, or B is concave under it), a fracture
//     triangle with a corner on B pokes out of B (sampled on a grid): the build starts again
//     with its S vertices off B pushed into B from the deepest poke toward its closest point on
//     B (not along the normal nearest the vertex: on a thin B the poke may cross the far side),
//     a quarter farther than each alone would have to go to take the deepest poke back, at most
//     the vertex's shortest edge over 8 rounds, and only while S stays free of
//     self-intersections; a vertex that would have to go farther is contracted into its nearest
//     neighbour instead, and when that contraction is refused, into the next nearest, and so
//     on. (Step 0 already moved every rim vertex whose inner edge leaves it
//     outside B to where that edge enters B, unless S would then cross itself.)
// 3c. Clashes. The fracture triangles and the cut B triangles are tested for intersections
//     exactly (the grid of 3b can miss a thin poke). A fracture triangle through a B triangle
//     pushes its S vertices off B as in 3b (a tenth of their shortest edge per round, along the
//     inward normal of the B triangles crossed); two
//     fracture triangles through each other (a pleat of S next to the rim: tiny faces folded
//     onto each other, crossed once the traces bend the rim faces toward B) start the build
//     again with the shortest edge at their S vertices off B contracted (one per attempt, only
//     while S stays valid and free of self-intersections); when every such edge has been tried,
//     those vertices move a quarter further toward the centroid of their neighbours per attempt,
//     up to all the way, again only while S stays free of self-intersections.
//  4. Patches. The cut B is flood-filled across its edges that are not on a trace. A patch face
//     using the directed cut edge (x, y) in the winding direction of the S face on that edge
//     belongs to that face's front piece, in the opposite direction to its back piece; every cut
//     edge of a patch must agree. A B component no trace touches goes to the piece on the side of
//     the S face nearest to it (to piece 0 when S has no faces).
//  5. Merge. Each piece is its patches (inside = 0) plus its S faces wound outward (inside = 1).
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/mesh_soup.hpp"
#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// vertex_origin value of a vertex inserted where a trace crosses a B edge.
inline constexpr std::int64_t kCrossing = std::numeric_limits<std::int64_t>::min();

/// vertex_origin value of a vertex added at the centroid of a fracture face (see FaceCentre).
inline constexpr std::int64_t kFaceCentre = kCrossing + 1;

/// vertex_origin value of a route point inside a B triangle (see RoutePoint).
inline constexpr std::int64_t kRoutePoint = kCrossing + 2;

/// A vertex added inside a face of S whose corners all lie on B and whose traced boundary bends
/// over a crease of B: no triangle among the face's own points would stay off B. It is the
/// centroid of the corners, or, for a needle-thin face whose centroid does not see every side,
/// another point of the face's triangle.
struct FaceCentre {
  std::uint32_t vertex = 0;               ///< index in PieceSet::positions
  std::uint32_t s_face = 0;               ///< the face of S (input numbering)
  std::array<std::uint32_t, 3> corners{};  ///< its S vertices
  glm::dvec3 weights{1.0 / 3.0};          ///< the point is the sum of weights[k] x corners[k]
};

/// A vertex inserted by the cut, where the trace of an S boundary edge crosses an edge of B.
struct CrossingPoint {
  std::uint32_t vertex = 0;          ///< index in PieceSet::positions
  std::uint32_t s_from = 0, s_to = 0;  ///< the S boundary edge, in the direction it was traced
  double along = 0.0;                ///< fraction of the trace's length from s_from, in (0, 1)
  std::uint32_t b_from = 0, b_to = 0;  ///< the crossed B edge (b_from < b_to)
  double t = 0.0;                    ///< the point is b_from + t (b_to - b_from), t in (0, 1)
};

/// A vertex inside a B triangle through which the trace of an S boundary edge was re-routed to
/// keep clear of the trace of a neighbouring boundary edge (step 2b). Like a crossing point it
/// lies on B and on the side of the S face of that edge. (A route point that lands on a B edge
/// is recorded as a CrossingPoint, one that lands on a B vertex is that vertex.)
struct RoutePoint {
  std::uint32_t vertex = 0;            ///< index in PieceSet::positions
  std::uint32_t s_from = 0, s_to = 0;  ///< the S boundary edge, in the direction it was traced
  double along = 0.0;                  ///< fraction of the trace's length from s_from, in (0, 1)
  std::uint32_t b_face = 0;            ///< the B triangle holding it
  glm::dvec3 bary{0.0};                ///< weights of b_face's corners at the point
  std::uint32_t clear_from = 0, clear_to = 0;  ///< the S boundary edge whose trace it keeps clear of
};

/// One closed mesh per piece, all indexing one shared vertex array.
struct PieceSet {
  /// Every vertex of every piece. Index layout: [0, S vertices) are the vertices of S in their
  /// order (boundary ones moved onto B, those pushed inward by step 3b moved, the others
  /// converted to double as they are); then the
  /// vertices of B in their order, less those an S vertex was snapped onto (that S vertex takes
  /// their place); then the crossing points and route points, in the order of the traces
  /// (each list in `crossings` and `route_points` ascending); then the face centres, in the
  /// order of `face_centres`.
  std::vector<glm::dvec3> positions;
  struct Piece {
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into positions, outward
    std::vector<std::uint8_t> inside;  ///< per triangle: 1 = fracture face (from S), 0 = exterior (from B)
  };
  std::vector<Piece> pieces;  ///< index = piece id of S
  /// Per position: >= 0 the S vertex it is; -1 - b for B vertex b; kCrossing for a crossing
  /// point (described by `crossings`); kRoutePoint for a route point (`route_points`);
  /// kFaceCentre for a face centre (`face_centres`).
  std::vector<std::int64_t> vertex_origin;
  std::vector<CrossingPoint> crossings;  ///< ascending vertex
  std::vector<RoutePoint> route_points;  ///< ascending vertex
  std::vector<FaceCentre> face_centres;  ///< ascending vertex
  std::uint32_t s_vertex_count = 0;      ///< vertices of S (the first positions)
  std::uint32_t snapped_to_b_vertex = 0; ///< S boundary vertices that landed on a B vertex
  std::uint32_t boundary_edges_merged = 0;  ///< short boundary edges of S contracted (their
                                            ///< removed end stays in positions, unused)
  std::uint32_t flaps_removed = 0;          ///< faces of S lying flat on B, left out
  std::uint32_t rim_retracted = 0;          ///< S boundary vertices moved to where S enters B (step 0)
  std::uint32_t pushed_inward = 0;          ///< S vertices off B moved inward by step 3b
  std::uint32_t relaxed = 0;                ///< S vertices off B moved toward their neighbours (step 3c)
  std::uint32_t attempts = 1;               ///< builds made (the last succeeded; see steps 3 to 3c)
  std::uint32_t contracted = 0;             ///< S edges at a fold or a crossing of traces contracted (step 3c; the removed
                                            ///< end stays in positions, unused)
  std::uint32_t traces_rerouted = 0;        ///< route points added by step 2b (each a
                                            ///< RoutePoint, a CrossingPoint or a B vertex)
};

struct PieceOptions {
  /// Largest distance of an S boundary vertex from B, relative to B's bounding-box diagonal.
  /// The refiner projects in float (about 1e-7 off); farther means S does not end on B.
  double snap_tolerance = 1e-4;
  /// Barycentric weights below this are zeroed when locating an S vertex on B, so a vertex
  /// that was meant to lie on a B edge or vertex (up to float noise) lands exactly on it.
  double location_epsilon = 1e-6;
  /// B vertices closer than this (relative to B's diagonal) to a trace's plane are on it.
  double plane_epsilon = 1e-9;
  bool delaunay = true;  ///< improve the re-triangulated B triangles by Delaunay flips
  /// Boundary edges of S shorter than this (relative to B's diagonal) are contracted before
  /// the cut (0 = never): two boundary vertices a hair apart leave a face that would have to
  /// lie in B wherever the next trace bends over a crease.
  double merge_tolerance = 1e-4;
  /// Remove faces of S with two or three boundary edges that lie flat on B, are needle-thin or
  /// cannot be re-triangulated (flaps): they bound no volume and would fold a piece onto itself.
  bool remove_flaps = true;
};

/// Cuts B along the boundary of S and builds one closed mesh per piece of S (see the file
/// comment for the method).
/// \throw InputError when `exterior` has no triangles, an index out of range, a non-finite
///        coordinate, an edge that does not have exactly two faces in opposite directions, or
///        a negative volume (wound inward).
/// \throw RunError "the fracture surface is not valid: <validate()'s message>" when S breaks an
///        invariant once its derived arrays are rebuilt.
/// \throw RunError naming the S vertex, S edge, S face or B triangle when S does not fit B:
///        a boundary vertex of S farther than snap_tolerance from B, two S vertices on the same
///        point of B, a trace that cannot reach its end, traces that cross or touch (after step
///        2b), a face whose polygon cannot be triangulated (after the retries of step 3), faces
///        still poking out of B after the pushes of step 3b (or a push that would make S
///        intersect itself), triangles still intersecting after the retries of step 3c, a patch
///        that borders two different pieces.
PieceSet build_pieces(const FractureSurface& s, const MeshSoup& exterior, const PieceOptions& options = {});

/// What check_pieces finds about one piece.
struct PieceCheck {
  std::size_t triangles = 0;
  std::size_t inside_triangles = 0;   ///< from S
  double volume = 0.0;                ///< signed, by the divergence theorem
  std::size_t open_edges = 0;         ///< undirected edges with one face
  std::size_t non_manifold_edges = 0; ///< edges with three or more faces
  std::size_t misoriented_edges = 0;  ///< edges with two faces using it in the same direction
  std::size_t self_intersections = 0;  ///< pairs of faces (exact; capped at max_self_intersections)
  bool closed() const { return open_edges == 0; }
  bool edge_manifold() const { return non_manifold_edges == 0 && misoriented_edges == 0; }
  bool outward() const { return volume > 0.0; }
};

struct PieceCheckOptions {
  std::size_t sample_points = 2000;  ///< random points inside B tested against every piece
  std::uint64_t seed = 1;
  double volume_tolerance = 1e-3;    ///< allowed relative error of the sum of piece volumes
  std::size_t max_self_intersections = 16;  ///< per piece, stop counting after this many
  int threads = default_threads();
};

/// The partition check of a piece set against its exterior.
struct PieceReport {
  std::vector<PieceCheck> pieces;
  double exterior_volume = 0.0;
  double volume_sum = 0.0;
  double volume_relative_error = 0.0;  ///< |volume_sum - exterior_volume| / |exterior_volume|
  std::size_t points_tested = 0;
  std::size_t points_in_no_piece = 0;
  std::size_t points_in_several_pieces = 0;
  /// One line per failure, naming the piece and why, e.g. "piece 3: not closed (2 open edges)";
  /// empty when every check passed.
  std::vector<std::string> failures;
  bool ok() const { return failures.empty(); }
};

/// Checks every piece (closed, edge-manifold, outward, no self-intersections, not empty) and
/// the partition (volumes sum to B's within volume_tolerance; each of sample_points random
/// points inside B, drawn from a seeded generator, lies in exactly one piece).
/// \throw InputError when `exterior` has no triangles or bad indices.
/// \throw RunError when `pieces` has an index out of range.
PieceReport check_pieces(const PieceSet& pieces, const MeshSoup& exterior, const PieceCheckOptions& options = {});

/// \throw RunError listing report.failures when the report is not ok.
void require_valid_pieces(const PieceReport& report);

/// "piece_NNN" (at least 3 digits): the file and node name of piece p.
std::string piece_name(std::size_t p);

/// Creates `folder`/pieces and calls write(dir, p, piece) for every piece, in order: the loop
/// both piece writers (PLY here, OBJ in animate) share.
/// \throw RunError when the folder cannot be created or a piece's inside flags do not match its
///        triangles.
void for_each_piece_file(const PieceSet& pieces, const std::filesystem::path& folder,
                         const std::function<void(const std::filesystem::path& dir, std::size_t p,
                                                  const PieceSet::Piece& piece)>& write);

struct PieceWriteOptions {
  bool ply_binary = true;
};

/// Writes `folder`/pieces/piece_<NNN>.ply (NNN = piece id, at least 3 digits) through
/// write_mesh. A piece's file holds only the vertices it uses, in ascending shared index: vertex
/// properties mx, my, mz (double, the material-space position, here the position itself), face
/// property inside (uchar). The OBJs are write_piece_objs' (animate/piece_surface.hpp).
/// \throw RunError when a file cannot be written.
void write_pieces(const PieceSet& pieces, const std::filesystem::path& folder, const PieceWriteOptions& options = {});

}  // namespace fracref
