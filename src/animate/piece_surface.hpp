#pragma once
// What an artist's tools need on top of a piece's triangles: split normals (smooth within the
// exterior and within the fracture surface, hard at the crack rim) and texture coordinates from
// the material-space position. Shared by animation.glb and the piece OBJ files.
//
// A piece's n vertices keep their ids 0..n-1; each rim vertex (used by both an outside and an
// inside face) gets a second id n + k (k: its rank among the rim vertices, ascending), which
// the inside faces use. A vertex's normal is the area-weighted mean of the normals of its faces
// of one material: the outside faces for ids < n that have any, the inside faces otherwise.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "pieces/pieces.hpp"

namespace fracref {

struct SplitPiece {
  std::size_t vertex_count = 0;       ///< n
  std::vector<std::uint32_t> rim;     ///< the rim vertices, ascending; copy k is vertex n + k
  std::vector<std::array<std::uint32_t, 3>> outside, inside;  ///< faces on split ids, in input order
  std::vector<glm::dvec3> normals;    ///< unit, per split id (n + rim.size())
  /// The original vertex of split id i.
  std::uint32_t original(std::size_t i) const {
    return i < vertex_count ? std::uint32_t(i) : rim[i - vertex_count];
  }
};

/// Splits the piece whose faces are `faces` (on ids < positions.size()) with per-face `inside`
/// flags, computing normals from `positions`. A vertex whose faces have no area takes the first
/// non-degenerate normal of its faces, or +z.
/// \pre faces.size() == inside.size(); every id < positions.size().
SplitPiece split_piece(const std::vector<std::array<std::uint32_t, 3>>& faces, const std::vector<std::uint8_t>& inside,
                       const std::vector<glm::dvec3>& positions);

/// Box projection of a material-space position: the two coordinates of (material - lo) / scale
/// other than the dominant axis of `normal` (x dominant: (y, z); y: (z, x); z: (x, y)); ties go to
/// the first axis. \pre scale > 0.
glm::dvec2 box_texcoord(const glm::dvec3& material, const glm::dvec3& normal, const glm::dvec3& lo, double scale);

/// Writes `folder`/pieces/piece_NNN.obj and pieces.mtl: a piece's vertices in ascending shared
/// index (as write_pieces' PLY), one `vn` per split id, the outside faces under `usemtl outside`
/// then the inside ones under `usemtl inside`, as `f v//vn`: split normals.
/// \throw RunError when a file cannot be written.
void write_piece_objs(const PieceSet& pieces, const std::filesystem::path& folder);

}  // namespace fracref
