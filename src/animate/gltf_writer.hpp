#pragma once
// The high-resolution animation as one glTF 2.0 binary (OUT/animation.glb), for Blender,
// three.js and any other glTF 2.0 reader. Self-contained: no external library; the JSON is
// written by hand in a fixed order, so the same input gives the same bytes.
//
// Layout of the file (glTF 2.0, "GLB" container, little-endian):
//  - header: magic 0x46546C67 ("glTF"), version 2, total length; then a JSON chunk padded with
//    spaces and a BIN chunk padded with zeros, each a multiple of 4 bytes long.
//  - one node and one mesh per piece, both named piece_NNN (as in pieces/ and frames/), in
//    piece order, all in scene 0. A mesh has up to two primitives sharing its vertex arrays:
//    "exterior" (the faces from B, material `exterior`, grey) and "inside" (the fracture faces,
//    material `inside`, a warm colour); a primitive with no face is left out. Vertex i < n of a
//    mesh is vertex i of pieces/piece_NNN.ply (n vertices); vertex n + k is a second copy of the
//    k-th rim vertex (used by both materials, ascending), which the inside faces use, so that
//    normals are split at the crack rim (piece_surface.hpp). Faces are in the order of
//    pieces/piece_NNN.obj. Indices uint32; attributes float32: POSITION, NORMAL (smooth per
//    material), _MATERIAL_POSITION (the material-space position), and on the inside primitive
//    TEXCOORD_0 (box_texcoord of the material position, in the pieces' material bounding box).
//  - a piece is rigid when every frame is a rotation and translation of its rest pose within
//    GltfOptions::rigid_tolerance (rigid_fit.hpp; checked with the float values written). Its
//    mesh is the rest pose less its pivot (the rest vertices' centroid), and its node carries
//    frame 0's translation and rotation. Every other piece deforms: its mesh is frame 0, and
//    every further kept frame is one morph target of POSITION deltas (sparse when most
//    vertices do not move; without data when none does), named frame_NNNN in
//    mesh.extras.targetNames. Every POSITION accessor, targets included, carries min and max.
//  - one animation "fracture", keyed at the kept frames' times (frame / fps seconds), LINEAR:
//    per rigid piece a `translation` and a `rotation` channel, per deforming piece a `weights`
//    channel (at the kept frame j the unit vector of target j, all zero at frame 0); all share
//    the input. animations[0].extras holds `frame_count` (frames of the animation) and
//    `frame_step` (see GltfOptions).
//  With a single frame there are no morph targets and no animation.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "animate/animate.hpp"
#include "coarse/animation.hpp"
#include "pieces/pieces.hpp"

namespace fracref {

struct GltfOptions {
  /// Budget in bytes for the file (positions, indices, morph targets, animation keys, and an
  /// allowance of 256 bytes of JSON per piece and kept frame). Morph targets grow as kept
  /// frames x vertices x 12 bytes (and the weight keys as kept frames squared x 4): when keeping
  /// every frame would exceed the budget, only frames 0, k, 2k, ... and the last are kept, with
  /// k the smallest step that fits. The first and the last
  /// frame are always kept, even over the budget. Peak memory while encoding is about twice
  /// the file size (the data, then the file).
  std::size_t max_bytes = std::size_t(256) << 20;
  /// A piece is rigid when no vertex is further than this fraction of the pieces' material
  /// bounding-box diagonal from where its fitted node transform puts it, in any frame.
  double rigid_tolerance = 1e-6;
  /// When set, the fracture faces carry COLOR_0: this colour (linear RGB in [0, 1]) at each
  /// vertex's material-space position, and their material's base colour is white so that the
  /// vertex colours show as they are (the material's own colours, or ζ's ramp).
  std::function<glm::vec3(const glm::dvec3& material_position)> inside_color;
  /// With inside_color: the exterior faces carry it too (COLOR_0 on a white `exterior`
  /// material), for a material whose own colours show on its outside as well (marble, wood,
  /// jelly), unlike ζ's ramp.
  bool color_exterior = false;
};

/// What encode_animation_glb wrote.
struct GltfSummary {
  std::size_t frame_count = 0;  ///< frames of the animation
  std::size_t frame_step = 1;   ///< k: frames 0, k, 2k, ... and the last one are kept
  std::size_t frames_kept = 0;  ///< animation keys (morph targets per deforming mesh + 1)
  std::size_t rigid_pieces = 0; ///< pieces moved by node transforms
  std::size_t bytes = 0;        ///< size of the GLB file
  bool over_budget = false;     ///< even the first and last frames alone exceed max_bytes
};

/// The frames a step keeps: 0, step, 2 step, ... and frame_count - 1, ascending.
/// \pre step >= 1.
std::vector<std::size_t> gltf_kept_frames(std::size_t frame_count, std::size_t step);

/// The animation of `pieces` in `result` as the bytes of a GLB file (layout: the file comment).
/// \pre `result` was computed for `pieces` (animate_pieces).
/// \throw RunError when `result` has no frame, fps not > 0, a frame without one position per
///        slot, a non-finite position, a piece without triangles, a layout that does not fit
///        `pieces` (write_frames' messages), or when the file would reach 4 GiB (the GLB limit).
std::string encode_animation_glb(const PieceSet& pieces, const AnimationResult& result, const GltfOptions& options = {},
                                 GltfSummary* summary = nullptr);

/// encode_animation_glb written to `file` through write_file_atomic.
/// \throw RunError as encode_animation_glb, or when the file cannot be written.
GltfSummary write_animation_glb(const PieceSet& pieces, const AnimationResult& result, const std::filesystem::path& file,
                                const GltfOptions& options = {});

/// The same, evaluating one kept frame at a time with transfer_frame (memory: the file and one
/// frame). \pre `transfer` was built from `animation` and `pieces`.
GltfSummary write_animation_glb(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                                const std::filesystem::path& file, const GltfOptions& options = {});

}  // namespace fracref
