#pragma once
// The user strength grid file (scene `field.type: "grid"`): a short text header, then the node
// values, x fastest. Format documented in scenes/INPUTS.md, section "Strength grid":
//
//   fracref-grid 1
//   dims 32 32 64
//   origin -1.0 -1.0 -4.0
//   cell 0.125
//   format float32-le        (or: text)
//   end_header
//   <nx*ny*nz values>
#include <filesystem>

#include "field/grid.hpp"

namespace fracref {

/// Reads a strength grid file strictly.
/// \return the grid: dims, origin, cell and nx*ny*nz finite values (x fastest).
/// \throw InputError "<file>:<line>: ..." for a header or text-value error (bad magic, unknown,
///        repeated or missing key, dims outside [2, 1024], non-positive or non-finite cell or
///        origin, unknown format, a bad number, a NaN/inf value, too few or too many values), and
///        "<file>: byte <offset>: ..." for binary data (truncated, trailing bytes, NaN/inf value);
///        "<file>: ..." when the file cannot be read or is larger than max_input_file_bytes().
Grid3 read_strength_grid(const std::filesystem::path& file);

/// read_strength_grid(), then checks the grid against the scene: it must cover the box
/// [lo, hi] (the exterior's bounding box, up to 1e-9 of its diagonal), and when `resolution` is
/// not {0,0,0} (the scene gave `field.resolution`) its dims must equal it.
/// \throw InputError as read_strength_grid(), or "<file>: the grid covers [..] but the exterior's
///        bounding box is [..]" / "<file>: dims .. differ from the scene's field.resolution ..".
Grid3 load_strength_grid(const std::filesystem::path& file, const glm::dvec3& lo, const glm::dvec3& hi,
                         const glm::uvec3& resolution);

/// Writes `grid` in the format read_strength_grid() reads, atomically (temporary file + rename);
/// `binary` selects float32-le values, otherwise text with 9 significant digits (exact for floats).
/// \pre grid.values.size() == grid.size(); dims in [2, 1024]; cell > 0.
/// \throw RunError when the file cannot be written.
void write_strength_grid(const std::filesystem::path& file, const Grid3& grid, bool binary);

}  // namespace fracref
