#pragma once
// The low-resolution fracture (paper section 4.1, docs/DESIGN.md "Pipeline", steps 1-2): what every
// coarse input kind becomes. A tetrahedral mesh with a piece label per tet (what a FEM fracture
// simulator leaves) or a set of closed pre-fractured pieces (what Blender Cell Fracture, Houdini
// or Blast export) is turned into a CoarseModel holding the canonical fracture surface S.
//
// Welding. Coarse vertices that coincide in material space (within a relative tolerance of the
// bounding-box diagonal) are one point of the material: a simulator duplicates vertices where a
// crack opens, and every exported piece carries its own copy of its cut faces. Topology (which
// faces touch, what S is) is computed on welded vertices; the model keeps every input vertex so
// each piece can move with its own copy (see CoarseModel::vertex_weld).
//
// Pieces are the face-connected components of the material once every cut is made. Input piece
// labels are relabelled compactly in ascending order; a label whose tets fall into several
// components (split by virtual fracture, by a crack, or simply disconnected) keeps its id for the
// component holding its lowest tet, and the other components get new ids after all input labels,
// in the order of their lowest tet.
//
// Orientation of S: every face's normal points into the piece with the LARGER id (its front).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/mesh_soup.hpp"
#include "surface/fracture_surface.hpp"
#include "util/error.hpp"

namespace fracref {

/// How pieces that do not conform exactly were fitted (src/coarse/pieces_fit.hpp); all zero and
/// `fitted` false for every other input, and for pieces that conform.
struct PiecesFit {
  bool fitted = false;          ///< S is the label boundary of a tet lattice of B (not the pieces' own faces)
  std::string reason;           ///< why the exact path refused the pieces (its message)
  double tolerance = 0.0;       ///< widest gap closed, scene units
  double cell = 0.0;            ///< the lattice's cell, scene units
  std::size_t tets = 0;         ///< tets of the lattice inside B
  double gap_volume = 0.0;      ///< volume of the tets whose centre lies in no piece (assigned to the nearest)
  double overlap_volume = 0.0;  ///< volume of the tets whose centre lies in two or more pieces
  double pieces_volume = 0.0;   ///< sum of the pieces' own (signed) volumes
  double exterior_volume = 0.0; ///< B's volume
  std::size_t tets_relabelled = 0;  ///< by the clean-ups: stray islands merged, wedges S cannot represent relabelled
  std::vector<std::string> grown;   ///< pieces thinner than the cell, given the one tet nearest them
};

/// The coarse model, whatever input it came from.
struct CoarseModel {
  std::vector<glm::dvec3> vertices;  ///< material-space positions of the coarse vertices (unwelded)
  std::vector<glm::uvec4> tets;      ///< positively oriented (det[b-a, c-a, d-a] > 0); empty for pieces
  std::vector<int> tet_piece;        ///< per tet, piece in [0, piece_count)
  int piece_count = 0;
  /// The canonical coarse fracture surface S, on welded vertices. Its vertices are numbered
  /// compactly (only welded vertices used by S), in ascending model-vertex order.
  FractureSurface surface;
  /// Per vertex of S, its welded model vertex (the lowest model vertex at that position).
  std::vector<std::uint32_t> surface_to_model_vertex;
  /// Per entry of surface.copies (vertex s of S as seen by piece p), the model vertex piece p
  /// uses there: the lowest one among the corners of p's tets (or p's own vertices) welded to s.
  std::vector<std::uint32_t> surface_copy_model_vertex;
  /// Per model vertex, the lowest model vertex it is welded to (itself when alone); always <= v.
  std::vector<std::uint32_t> vertex_weld;
  std::vector<glm::uvec3> hull;  ///< the coarse exterior, model vertex ids, wound outward
  std::vector<int> hull_piece;   ///< piece of each hull face
  /// Per piece, a name for messages: "label 3" / "label 3, part 2" for tets, the OBJ group name
  /// or file name for pieces.
  std::vector<std::string> piece_names;
  double virtual_area_added = 0.0;       ///< area of the faces cut by virtual fracture
  std::size_t virtual_faces_added = 0;   ///< faces cut by virtual fracture
  std::size_t inverted_fixed = 0;        ///< tets (or pieces) given inside out and reoriented
  PiecesFit fit;                         ///< pieces fitted on a lattice (pieces_fit.hpp), or not
};

// ------------------------------------------------------------------------------------------------
// Tetrahedral input

/// A labelled tet mesh as a reader (or a caller) gives it.
struct TetMesh {
  std::string file;                    ///< names the source in messages ("" = built in memory)
  std::vector<glm::dvec3> vertices;
  std::vector<glm::uvec4> tets;        ///< 0-based vertex ids, either orientation
  std::vector<std::int64_t> labels;    ///< per tet, piece label >= 0 (any values)
  std::vector<std::size_t> tet_lines;  ///< per tet, its line in `file`; empty when built in memory
};

/// Faces cracked inside one piece (a cut that does not separate by itself).
struct CrackList {
  std::string file;
  std::vector<glm::uvec3> faces;   ///< model vertex ids, 0-based
  std::vector<std::size_t> lines;  ///< per face, its line in `file`
};

struct TetModelOptions {
  /// Extend non-separating cuts until every cut separates (paper 4.1). When false, a cut that
  /// does not separate its piece is an InputError.
  bool virtual_fracture = true;
  /// Vertices closer than this fraction of the bounding-box diagonal (per coordinate) are welded.
  double weld_tolerance = 1e-9;
  /// Give every label its own copy of the vertices it shares with other labels (what a mesher
  /// writes, one vertex per point, is then animated by per-piece rigid transforms: each piece
  /// moves its own copies). Topology is unchanged: the copies weld back together.
  bool own_vertices = false;
};

/// Builds the coarse model of a labelled tet mesh.
///
/// Cut faces: an interior face between tets of different labels; an interior face whose two tets
/// use different (welded) vertex copies, i.e. a crack the simulator opened; a face of `cracks`.
/// With options.virtual_fracture, cuts are extended by extend_cracks() before the pieces are
/// flood-filled. S is every cut face; the hull is every face of one tet only.
/// \pre cracks may be null (no cracks file).
/// \throw InputError naming mesh.file and the tet's line (or "tet N" in memory) for: no tet, an
///        index out of range, a label < 0, a non-finite position, a zero-volume tet (exact
///        orient3d, after welding), a face shared by 3+ tets, two tets on the same side of a face;
///        naming cracks->file:line for a crack index out of range, a crack that is not an
///        interior face, lies between two pieces already, or repeats an earlier line; and for a
///        cut that still does not separate its piece (with virtual fracture off, or around a
///        handle of the piece).
/// Inverted tets are reoriented (two vertices swapped) and counted in inverted_fixed.
CoarseModel build_tet_model(const TetMesh& mesh, const CrackList* cracks, const TetModelOptions& options = {});

/// Reads a MEDIT `.mesh` or TetGen `.node`/`.ele` (by extension), the optional cracks file
/// (empty path = none), and builds the model. \throw InputError as the readers and build_tet_model.
CoarseModel load_tet_model(const std::filesystem::path& mesh, const std::filesystem::path& cracks,
                           const TetModelOptions& options = {});

// ------------------------------------------------------------------------------------------------
// Pre-fractured pieces

/// One closed piece as read from a file (or an OBJ group).
struct PieceInput {
  std::string name;  ///< OBJ group name or file name, for messages and CoarseModel::piece_names
  std::string file;  ///< source file for messages
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> triangle_polygon;  ///< per triangle, its polygon (fan) in the piece, from 0
};

/// The pieces are well formed but do not conform exactly (degenerate, open or non-manifold
/// faces, cut faces that do not match, a repeated or overlapping face): build_pieces_model()
/// throws it where fit_pieces_model() (pieces_fit.hpp) can still make a fracture surface.
class PiecesMismatch : public InputError {
 public:
  using InputError::InputError;
};

struct PiecesOptions {
  /// Positions of different pieces closer than this fraction of the bounding-box diagonal (per
  /// coordinate) are the same point. 1e-9 suits double-precision exports; files written with 6
  /// decimals (Blender's OBJ exporter) may need about 1e-6.
  double weld_tolerance = 1e-9;
  /// Faces of different pieces whose corners are within this fraction of the diagonal of each
  /// other's plane, and whose interiors overlap there, must match exactly (non-conformity check).
  double coplanar_tolerance = 1e-7;
};

/// Builds the coarse model of pre-fractured pieces. Every piece must be closed: each edge used by
/// exactly two of its faces, in opposite directions (after welding). A piece with negative volume
/// is reversed and counted in inverted_fixed. Polygons (then triangles) of two different pieces
/// on the same welded vertices with opposite winding are a cut: one face of S (the smaller
/// piece's triangulation). Faces matching no other piece are the hull.
/// Model vertices are one per (piece, welded position), pieces in order, then by first use.
/// \throw InputError naming the file and piece for: no piece, an empty piece, an index out of
///        range, a non-finite position;
/// \throw PiecesMismatch (an InputError) naming the file and piece for: a degenerate face, an
///        open or inconsistently wound piece, zero volume, a face repeated in a piece, a cut
///        face shared by 3+ pieces or wound the same way in two, and a NON-CONFORMING cut: a face
///        of one piece whose interior overlaps, in its plane, a face of another piece it does not
///        match vertex for vertex (T-junction, partial overlap) - naming both pieces and the face.
CoarseModel build_pieces_model(const std::vector<PieceInput>& pieces, const PiecesOptions& options = {});

/// The pieces of one OBJ (read_mesh) with one `o` or `g` group per piece, each piece's vertices
/// compacted in first-use order and its polygons numbered from 0.
/// \throw InputError as read_mesh, and when the file has no groups.
std::vector<PieceInput> read_pieces(const std::filesystem::path& obj);

/// One piece per mesh file (OBJ/OFF/PLY); groups inside a file are ignored.
/// \throw InputError as read_mesh, and for an empty list.
std::vector<PieceInput> read_pieces(const std::vector<std::filesystem::path>& files);

/// build_pieces_model(read_pieces(obj)).
CoarseModel load_pieces(const std::filesystem::path& obj, const PiecesOptions& options = {});

/// build_pieces_model(read_pieces(files)).
CoarseModel load_pieces(const std::vector<std::filesystem::path>& files, const PiecesOptions& options = {});

}  // namespace fracref
