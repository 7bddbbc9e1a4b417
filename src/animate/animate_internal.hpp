#pragma once
// Internal to the animate room: the steps of build_transfer, shared by its .cpp files.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "animate/animate.hpp"

namespace fracref::animate_detail {

using Tri = std::array<std::uint32_t, 3>;

/// Marks a pair whose fracture frame is not known (yet).
inline constexpr std::int64_t kUnknownFrame = -1;

/// Per coarse S vertex, its copies (piece, model vertex), pieces ascending.
struct CoarseCopies {
  std::vector<std::uint32_t> offsets{0};
  std::vector<glm::uvec2> copies;  ///< (piece, model vertex)
};

CoarseCopies coarse_copies(const CoarseModel& model);

/// The model vertex piece p uses at coarse S vertex s, or UINT32_MAX.
std::uint32_t copy_of(const CoarseCopies& c, std::uint32_t s, int piece);

/// Per refined S vertex (the first `count`), its leaves (coarse S vertex, weight), ascending by
/// leaf, weights below 1e-12 dropped. Memoised over the tree (parents are older vertices).
std::vector<std::vector<std::pair<std::uint32_t, double>>> all_leaves(const RefinementTree& tree, std::size_t count,
                                                                      std::size_t coarse_count);

/// Index of the pair (i, j), i < j, among n items: (0,1), (0,2), ..., (1,2), ...
inline std::size_t pair_index(std::size_t i, std::size_t j, std::size_t n) { return i * n - i * (i + 1) / 2 + (j - i - 1); }

/// Fills transfer.coarse_fracture_frame and transfer.shared (step 4 of the file comment).
void setup_fracture(AnimationTransfer& transfer, const CoarseModel& model, const CoarseAnimation& animation,
                    const PieceSet& pieces, const CoarseCopies& copies,
                    const std::vector<std::vector<std::pair<std::uint32_t, double>>>& leaves, double tolerance);

/// Fills transfer.elements, rest_inverse and the anchor -> element CSR (step 1).
/// `boundary` is, per piece, its coarse boundary triangles on model vertex ids.
void setup_deformation(AnimationTransfer& transfer, const CoarseModel& model, const std::vector<std::vector<Tri>>& boundary);

/// Index of anchor (m, p) in transfer.anchors, or UINT32_MAX.
std::uint32_t find_anchor(const AnimationTransfer& transfer, std::uint32_t model_vertex, int piece);

/// Per piece, its faces on piece-local vertex ids (the index in layout.vertices[p]), outside
/// faces first, then inside ones (the order of pieces/piece_NNN.obj), each with its inside flag.
struct LocalFaces {
  std::vector<std::vector<Tri>> faces;
  std::vector<std::vector<std::uint8_t>> inside;
};

/// `what` names the caller in messages. \throw RunError when the layout has another piece
/// count than `pieces`, or a piece uses a vertex the layout does not list.
LocalFaces local_faces(const PieceSet& pieces, const PieceLayout& layout, const char* what);

/// The `.mtl` text of the materials `outside` (exterior) and `inside` (fracture faces), with a
/// first comment line naming `what` ("pieces", "frames").
std::string material_library(const std::string& what);

}  // namespace fracref::animate_detail
