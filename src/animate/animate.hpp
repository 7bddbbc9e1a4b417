#pragma once
// High-resolution animation (paper section 5, "High-Resolution Animation Production";
// docs/DESIGN.md "Pipeline", step 6): the coarse animation's deformation is transferred to
// every vertex of every high-resolution piece, frame by frame.
//
// Method (build_transfer, then transfer_frame per frame):
//  1. Anchors. An anchor is a coarse model vertex m as seen by piece p. Its deformation in frame
//     t is an affine map X -> A(t) (X - X_m) + x_m(t), with X_m the rest (material) position and
//     x_m(t) the animated one. A(t) comes from (first that applies):
//       - kRigid: the rigid animation's transform of piece p (its 3x3 part);
//       - kTets: the mean of F = D_t D_0^-1 (D = [x1-x0, x2-x0, x3-x0]) over piece p's tets
//         incident to m (all tets incident to m when p has none there);
//       - kSurface: no tets and no transforms (an artist's pieces animated per vertex): the mean
//         of Sumner and Popovic's (2004) triangle deformation gradient, with the fourth vertex
//         along the normal scaled by 1/sqrt(|n|), over piece p's coarse boundary triangles
//         (its hull faces and its side of S) incident to m. Exact for rigid motion, and for
//         affine motion within each triangle's plane; not exact for general affine motion.
//     An anchor with nothing to average keeps A = identity (it then only translates).
//  2. Fracture vertices (PieceSet vertices of S). Vertex v seen from piece p: the refinement
//     tree gives its leaves k (coarse S vertices) with weights w_k; each leaf maps to the model
//     vertex m_k that piece p uses there (CoarseModel::surface_copy_model_vertex), and
//       x_v(t) = sum_k w_k (A_k(t) (X_v - X_k) + x_k(t)),   weights renormalised to sum to 1,
//     exact for affine motion. Leaves that piece p does not use are dropped (the rest
//     renormalised); with none left the vertex is treated as an exterior vertex (3).
//  3. Exterior vertices (B vertices and crossing points) of piece p: the closest point X_c of
//     piece p's coarse boundary (its hull faces and its side of S, in material space) with
//     barycentric weights l_i on the corners' anchors i:
//       x(t) = sum_i l_i (A_i(t) (X - X_c) + x_i(t)),
//     i.e. the interpolated affine map applied about the closest point; exact for affine motion.
//  4. Fracture time. The copies of a coarse S vertex in pieces p and q separate at the first
//     frame where their animated positions differ by more than separation_tolerance times the
//     bounding-box diagonal of the rest vertices (never: kNeverFractures). This is kept per PAIR
//     of pieces, so a junction vertex can open between two pieces and stay closed between
//     others. A refined S vertex separates between p and q at the MINIMUM over its leaves (that
//     have copies in both pieces): it opens as soon as any coarse corner of the region it came
//     from opens, as the coarse face itself does. A crossing point takes the minimum of the two
//     ends of its traced S edge; any other exterior vertex shared by several pieces (a B vertex
//     on a trace) takes, per pair, the minimum over its nearest (fewest-edge) shared neighbours
//     whose time is known. A pair with no defined time separates from frame 0.
//     In frame t, the pieces of a shared vertex whose pairs have not separated yet (joined
//     transitively) all take the AVERAGE of their transferred positions, so no crack opens
//     before the coarse animation opens it (paper Figure 8).
#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "coarse/animation.hpp"
#include "coarse/coarse_model.hpp"
#include "pieces/pieces.hpp"
#include "refine/topology_edit.hpp"

namespace fracref {

/// Fracture frame of a pair of copies that never separate.
inline constexpr std::int64_t kNeverFractures = std::numeric_limits<std::int64_t>::max();

struct AnimateOptions {
  /// Two copies of a coarse vertex are separated once their distance exceeds this fraction of
  /// the bounding-box diagonal of the coarse rest vertices.
  double separation_tolerance = 1e-5;
};

/// Where each piece's vertices live in a frame's flat position array ("slots").
struct PieceLayout {
  /// Per piece, the PieceSet vertices it uses, ascending: the vertex order of
  /// pieces/piece_NNN.ply and .obj (write_pieces).
  std::vector<std::vector<std::uint32_t>> vertices;
  /// Per piece, its first slot; one more entry at the end (the slot count).
  std::vector<std::uint32_t> offsets{0};
  std::size_t slot_count() const { return offsets.back(); }
};

/// Where the anchors' affine maps come from (see the file comment, step 1).
enum class DeformationSource : std::uint8_t { kRigid, kTets, kSurface };

/// One term of a slot's position: weight * (A_anchor(t) * offset + x_anchor(t)).
struct TransferTerm {
  std::uint32_t anchor = 0;
  double weight = 0.0;
  glm::dvec3 offset{0.0};  ///< X - X_m (refined vertex) or X - X_c (exterior vertex)
};

/// A PieceSet vertex used by two or more pieces, and when each pair of them separates.
struct SharedVertex {
  std::uint32_t vertex = 0;            ///< PieceSet vertex
  std::vector<int> pieces;             ///< pieces using it, ascending
  std::vector<std::uint32_t> slots;    ///< its slot in each of those pieces
  /// For pieces[i] < pieces[j], in the order (0,1), (0,2), ..., (1,2), ...: the first frame in
  /// which the two sides are apart (kNeverFractures: never).
  std::vector<std::int64_t> pair_fracture;
};

/// Everything needed to evaluate any frame (see the file comment).
struct AnimationTransfer {
  PieceLayout layout;
  DeformationSource source = DeformationSource::kSurface;
  std::vector<glm::uvec2> anchors;  ///< (model vertex, piece), ascending
  /// Per anchor, the elements whose deformation gradients it averages (tets for kTets,
  /// coarse boundary triangles for kSurface; empty for kRigid), as a CSR.
  std::vector<std::uint32_t> anchor_element_offsets{0}, anchor_elements;
  std::vector<glm::uvec4> elements;      ///< model vertex ids (w unused for triangles)
  std::vector<glm::dmat3> rest_inverse;  ///< per element, the inverse of its rest edge matrix (0: degenerate, skipped)
  std::vector<std::uint32_t> term_offsets{0};  ///< per slot, its terms (CSR)
  std::vector<TransferTerm> terms;
  std::vector<SharedVertex> shared;  ///< ascending vertex
  /// Per coarse S vertex, the first frame any two of its copies are apart (kNeverFractures: never).
  std::vector<std::int64_t> coarse_fracture_frame;
  std::size_t model_vertex_count = 0;
  std::size_t frame_count = 0;
  std::size_t nearest_fallbacks = 0;  ///< fracture-vertex slots placed as exterior vertices (no usable leaf)
  std::size_t identity_anchors = 0;   ///< anchors with no element to average (A = identity)
};

/// Precomputes the transfer of `animation` to every vertex of every piece.
/// \pre `tree` is the refinement tree of the refined S that `pieces` was built from, whose
///      first vertices are model.surface's (so tree leaves are coarse S vertex ids), and
///      `pieces` is in the material space of `model`.
/// \throw RunError naming what does not fit: no frame; a frame whose vertex count differs from
///        the model's; piece transforms present but not one per frame and piece; a PieceSet with
///        a different piece count; a tree shorter than the PieceSet's S vertices or a leaf that is
///        not a coarse S vertex; a piece whose coarse boundary is empty.
AnimationTransfer build_transfer(const CoarseModel& model, const CoarseAnimation& animation,
                                 const RefinementTree& tree, const PieceSet& pieces,
                                 const AnimateOptions& options = {});

/// The positions of every slot in frame `frame` (transfer.layout.slot_count() of them).
/// \pre `animation` is the one the transfer was built from. \throw RunError when frame is out of range.
std::vector<glm::dvec3> transfer_frame(const AnimationTransfer& transfer, const CoarseAnimation& animation,
                                       std::size_t frame);

/// Every frame at once.
struct AnimationResult {
  PieceLayout layout;
  /// Per frame, per slot: piece p's local vertex i is frames[t][layout.offsets[p] + i].
  std::vector<std::vector<glm::dvec3>> frames;
  std::vector<std::int64_t> coarse_fracture_frame;  ///< as AnimationTransfer's
  double fps = 24.0;
};

/// build_transfer, then transfer_frame for every frame. Memory: frames x slots x 24 bytes; for
/// long animations of large pieces use write_frames(pieces, transfer, animation, out), which
/// streams. \throw RunError as build_transfer.
AnimationResult animate_pieces(const CoarseModel& model, const CoarseAnimation& animation,
                               const RefinementTree& tree, const PieceSet& pieces,
                               const AnimateOptions& options = {});

/// How frames/ holds the animation (scenes/OUTPUTS.md).
enum class FramesFormat : std::uint8_t {
  kBinary,  ///< frames/topology.obj (frame 0) and frames/positions.bin (every frame's positions)
  kObj,     ///< frames/frame_NNNN.obj, one full OBJ per frame
};

/// The first 8 bytes of frames/positions.bin.
inline constexpr char kPositionsMagic[] = "FRFRAMES";

/// Writes `out`/frames/ in `format`, and `out`/frames/frames.mtl, each file complete or absent
/// (format: scenes/OUTPUTS.md). kObj: frame_NNNN.obj (NNNN = frame index from 0, at least 4
/// digits), each holding every piece as `o piece_NNN` with its own vertices, in the order of
/// layout.vertices, then its faces in the order of pieces/piece_NNN.obj (`usemtl outside` faces,
/// then `usemtl inside`). kBinary: topology.obj (that text for frame 0) and positions.bin
/// (a header, then per frame every slot's position as 3 float32).
/// \pre `result` was computed for `pieces`. 	hrow RunError when a file cannot be written, a
///      frame has not one position per slot, or the counts do not fit 32 bits.
void write_frames(const PieceSet& pieces, const AnimationResult& result, const std::filesystem::path& out,
                  FramesFormat format = FramesFormat::kObj);

/// The same, evaluating one frame at a time (memory: one frame, or two for kObj).
void write_frames(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                  const std::filesystem::path& out, FramesFormat format = FramesFormat::kObj);

}  // namespace fracref
