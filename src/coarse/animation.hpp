#pragma once
// The coarse animation (paper sections 4.1 and 5): per frame, the positions of the coarse model's
// vertices, from per-frame files (with backward remeshing) or from per-piece rigid transforms.
// Formats with examples: scenes/INPUTS.md.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "coarse/coarse_model.hpp"

namespace fracref {

struct CoarseAnimation {
  /// Per frame, the position of every model vertex (model.vertices.size() each).
  std::vector<std::vector<glm::dvec3>> frames;
  double fps = 24.0;
  /// frames form: per frame, how many vertices its file held (fewer than the model's before
  /// backward remeshing filled in the rest).
  std::vector<std::size_t> file_vertex_counts;
  /// rigid form: per frame, per piece, the transform (column-major, glm convention: x' = M * (x, 1)).
  std::vector<std::vector<glm::dmat4>> piece_transforms;
};

/// The path of frame number `frame`: the one `{}` or `{:0N}` field of `pattern` (N in 1..12)
/// replaced by the number, zero-padded to N digits for `{:0N}`.
/// \throw InputError naming the pattern when it has no such field, more than one, or other braces.
std::filesystem::path frame_file(const std::filesystem::path& pattern, std::int64_t frame);

/// Reads frames first .. first+count-1 of `pattern`.
///
/// A frame file ending in .obj, .off or .ply (any case) is read with read_mesh and only its
/// positions are used (faces are ignored); any other file is text: one `x y z` line per vertex,
/// '#' comments and blank lines allowed. Vertex v of every frame is model vertex v.
///
/// Without a parent map every frame must hold exactly model.vertices.size() vertices. With one
/// (backward remeshing, paper 4.1), frame vertex counts may grow over time (never shrink) up to
/// the model's, which is the LAST frame's topology, so the last frame must hold exactly that many.
/// Parent map lines are `v parent` (0-based): vertex v of the last frame's topology was split off
/// `parent`; parent must exist in the first loaded frame that has v (parent < that frame's vertex
/// count; entries for vertices present in every frame are allowed and unused). A frame with
/// n vertices gives each vertex v >= n the position of its ancestor: parent, parent's parent, ...
/// until one is < n.
/// \param parent_map_path empty: no parent map.
/// \throw InputError naming the file (and line for text): bad pattern, count < 1, first < 0,
///        fps not > 0; a missing or unreadable frame; a malformed line or non-finite number; a
///        frame with the wrong vertex count; counts that shrink; in the parent map: a malformed
///        line, v or parent out of range, v == parent, v listed twice, a cycle, a parent not in
///        the frame where v appears, a needed vertex with no parent.
CoarseAnimation load_frames(const std::filesystem::path& pattern, std::int64_t first, std::int64_t count, double fps,
                            const std::filesystem::path& parent_map_path, const CoarseModel& model);

/// Reads per-piece rigid transforms and applies them to the model's rest vertices.
///
/// One line per frame and piece: `frame piece r00 r01 r02 t0 r10 r11 r12 t1 r20 r21 r22 t2`
/// (the rows of the 3x4 matrix [R | t]; x' = R x + t), frame and piece 0-based, any order. The
/// frames are 0 .. F-1 with F - 1 the largest frame number, and every (frame, piece) pair of the
/// model's pieces must appear exactly once. R must be a rotation: |R^T R - I| <= 1e-4 per entry
/// and det R > 0.
/// A model vertex moves with the piece that uses it (its tets, or its hull and S faces). A vertex
/// used by several pieces is allowed only when those pieces have identical transforms in every
/// frame (as virtual pieces split from one input piece usually do); otherwise the model must
/// duplicate it (pieces input always does). Vertices used by no piece keep their rest position.
/// \throw InputError naming the file and line: malformed line, non-finite number, frame < 0,
///        piece out of range, repeated pair, non-rigid R; naming the file and the frame/piece for
///        a missing pair; for a shared vertex whose pieces move differently (naming the vertex,
///        both pieces and the line of the differing transform); fps not > 0.
CoarseAnimation load_rigid(const std::filesystem::path& transforms, double fps, const CoarseModel& model);

}  // namespace fracref
