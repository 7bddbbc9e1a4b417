#pragma once
// Watertight high-resolution pieces (paper section 5, "Exterior surface generation";
// docs/DESIGN.md, pipeline step 5): the exterior B is cut along the rim of the refined fracture
// surface S, split into patches, and every patch is merged with the faces of S that bound the
// same piece, giving one closed, edge-manifold, outward mesh per piece. Neighbouring pieces
// share their fracture vertices exactly (same index in one shared position array).
//
// Method (build_pieces), one pass, no repair: the refiner keeps S's rim embedded in B
// (rim/rim_on_b.hpp): every rim vertex has a location on B and every rim edge lies in one
// triangle of B.
//  1. Vertices. S's vertices (the rim ones at their locations, exactly on B), then B's vertices
//     less those a rim vertex lies on (that rim vertex takes their place).
//  2. Cut. Every B triangle that holds rim points is re-triangulated in its own barycentric
//     plane: a constrained triangulation with the rim segments as constraints, exact
//     orientation tests, Delaunay flips for shape (rim points on a B edge are shared by both
//     triangles of that edge, with exactly collinear coordinates).
//  3. Patches. The cut B is flood-filled across its edges that are not rim segments. A patch
//     face using the directed rim segment (x, y) in the winding direction of the S face on that
//     edge belongs to that face's front piece, in the opposite direction to its back piece;
//     every rim segment of a patch must agree. A B component the rim does not touch goes to the
//     piece on the side of the S face nearest to it (to piece 0 when S has no faces).
//  4. Merge. Each piece is its patches (inside = 0) plus its S faces wound outward (inside = 1).
// What cannot be made (rim segments that cross in a B triangle, a patch between two pieces) is
// an internal error naming the triangle or point: the refiner's edits are meant to exclude it.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/mesh_soup.hpp"
#include "rim/rim_on_b.hpp"
#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// One closed mesh per piece, all indexing one shared vertex array.
struct PieceSet {
  /// Every vertex of every piece. Index layout: [0, S vertices) are the vertices of S in their
  /// order (rim ones at their locations on B, the others converted to double as they are); then
  /// the vertices of B in their order, less those a rim vertex lies on.
  std::vector<glm::dvec3> positions;
  struct Piece {
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into positions, outward
    std::vector<std::uint8_t> inside;  ///< per triangle: 1 = fracture face (from S), 0 = exterior (from B)
  };
  std::vector<Piece> pieces;  ///< index = piece id of S
  /// Per position: >= 0 the S vertex it is; -1 - b for B vertex b.
  std::vector<std::int64_t> vertex_origin;
  std::uint32_t s_vertex_count = 0;       ///< vertices of S (the first positions)
  std::uint32_t snapped_to_b_vertex = 0;  ///< rim vertices of S that lie on a B vertex
  std::uint32_t rim_points_added = 0;     ///< vertices embed_rim added (the MeshSoup overload only)
};

struct PieceOptions {
  bool delaunay = true;  ///< improve the re-triangulated B triangles by Delaunay flips
  rim::EmbedOptions embed;  ///< for the overload that embeds the rim itself
};

/// Cuts B along S's rim and builds one closed mesh per piece of S (see the file comment).
/// \pre every rim vertex of S has its location in `rim`, and every rim edge lies in one triangle
///      of B (rim::find_unembedded_rim is empty); S valid.
/// 	hrow RunError "the fracture surface is not valid: <validate()'s message>" when S breaks an
///        invariant once its derived arrays are rebuilt; RunError naming the rim edge when the
///        precondition does not hold; an internal RunError naming the B triangle or point when the
///        rim segments cross in a B triangle or a patch borders two pieces.
PieceSet build_pieces(const FractureSurface& s, const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                      const PieceOptions& options = {});

/// build_pieces for an S whose rim lies on B but is not embedded yet (a coarse S, a test's
/// surface): a copy of S has its rim embedded (rim::embed_rim; its added vertices come after S's
/// own in PieceSet::positions, counted in rim_points_added), then the pieces are built.
/// 	hrow InputError when `exterior` is not a closed, manifold, outward mesh (rim::make_exterior_mesh);
///        RunError as rim::embed_rim and the overload above.
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
