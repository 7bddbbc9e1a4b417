#pragma once
// Strict mesh readers and writers for OBJ, OFF and PLY, in double precision.
//
// OpenMesh's own readers skip lines, drop faces and round to float without a word, so fracref
// reads user files with these readers instead. Every malformed input is an InputError whose
// message names the file, the line (text) or byte offset (binary), and the cause, e.g.
//   "mesh.obj:12: coordinate 'nan' is not finite"
//   "mesh.ply: byte 1234: file ends inside face 7 (truncated)"
// Accepted exactly as written (nothing merged, dropped or reoriented): non-manifold edges and
// vertices, inconsistent winding, unused vertices, quads and n-gons (triangulated in their own
// plane by ear clipping, non-convex ones included, and counted in
// MeshSoup::polygons_triangulated), CRLF line endings, and a
// UTF-8 byte order mark at the start of an OBJ or OFF file.
//
// Numbers are parsed with std::from_chars (exact, locale-free): one leading '+' is allowed on
// real numbers, nothing may trail a number, and NaN, infinities and values out of the range of
// a double (overflow, or underflow of a nonzero literal to zero) are errors.
//
// OBJ: accepted statements are `v x y z [w]` (a 4th component only when it is exactly 1:
// rational vertices are not supported), `vt u [v [w]]` and `vn x y z` (validated, not stored),
// `f` with `v`, `v/vt`, `v//vn` or `v/vt/vn` references (vt/vn references validated against the
// vt/vn counts), `o` and `g` (both start a group named by the rest of the line; no name means
// "default"), `s`, `usemtl`, `mtllib`, comments ('#' to the end of a line) and blank lines.
// `l`/`p` are errors ("line/point elements are not supported"); so is any other statement.
// Positive indices may refer to vertices defined later in the file (they are resolved after the
// whole file is read); negative indices are relative to the vertices defined so far (-1 = last).
// When any face lies in a group, faces before the first `o`/`g` belong to group "default".
// Line continuation with a trailing '\' is not supported (the backslash is a bad field).
//
// OFF: the first non-comment line is `OFF` (COFF, NOFF, 4OFF, ... are errors naming the
// variant), then `nv nf ne` (on their own line or after `OFF`; ne is not checked), then nv lines
// of exactly 3 coordinates and nf lines `n i0 .. in-1` with 0-based indices (face colors are not
// supported). One vertex or face per line; '#'
// comments and blank lines are allowed anywhere; data after the last face is an error.
//
// PLY: `format ascii 1.0` and `format binary_little_endian 1.0` (big-endian is an error naming
// it). Elements `vertex` (scalar properties x, y, z required, of any type; other scalar
// properties become MeshSoup::vertex_properties) and `face` (exactly one list property named
// `vertex_indices` or `vertex_index` with integer count and item types; other scalar properties
// become MeshSoup::face_properties, repeated on each triangle of a fan). Any other element, any
// other list property and unknown types are errors. ASCII data has one element per line; ASCII
// values are kept as written (a `float` property is not rounded to float) but must fit their
// declared type. Binary values are read little-endian and must be finite.

#include <filesystem>

#include "io/mesh_soup.hpp"

namespace fracref {

/// Reads an OBJ, OFF or PLY file, chosen by the extension (case-insensitive).
/// \throw InputError for an unknown or missing extension, a missing, unreadable or empty file,
///        and any malformed content (message: file, line or byte offset, cause).
MeshSoup read_mesh(const std::filesystem::path& path);

/// Reads a Wavefront OBJ file (see the file comment for the accepted subset).
/// \throw InputError as read_mesh.
MeshSoup read_obj(const std::filesystem::path& path);

/// Reads an OFF file. \throw InputError as read_mesh.
MeshSoup read_off(const std::filesystem::path& path);

/// Reads an ASCII or binary little-endian PLY file. \throw InputError as read_mesh.
MeshSoup read_ply(const std::filesystem::path& path);

/// Options of write_mesh.
struct MeshWriteOptions {
  bool ply_binary = true;  ///< PLY only: binary_little_endian (true) or ascii (false)
};

/// Writes `soup` as OBJ, OFF or PLY, chosen by the extension (case-insensitive), through
/// write_file_atomic: the file appears complete or not at all.
///
/// Text coordinates are written with 17 significant digits ("%.17g"), binary PLY positions as
/// little-endian doubles, so every double survives a write and a read bit for bit. Only
/// triangles are written (polygon structure is not kept). OBJ writes a `g` statement at every
/// change of group when `soup.groups` is not empty. Extra properties are written to PLY only,
/// with their declared types; OBJ and OFF leave them out.
/// \pre triangle indices < positions.size(); triangle_group empty or one entry per triangle.
/// \throw InputError for an unknown extension.
/// \throw RunError when the soup cannot be written faithfully (an index out of range, a property
///        column of the wrong length, a value that does not fit its type, a group name that
///        would not read back) or the file cannot be written.
void write_mesh(const std::filesystem::path& path, const MeshSoup& soup,
                const MeshWriteOptions& options = {});

}  // namespace fracref
