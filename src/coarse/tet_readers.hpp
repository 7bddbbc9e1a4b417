#pragma once
// Strict readers of tetrahedral meshes and crack lists. Every malformed input is an InputError
// naming the file, the line and the cause (as src/io does), e.g.
//   "bunny.mesh:42: tetrahedron index 913 is out of range (the file has 912 vertices; MEDIT indices start at 1)"
// Numbers are parsed locale-free and exactly (io_detail::parse_double / parse_int64): NaN,
// infinities and trailing characters are errors. '#' starts a comment in every format.
//
// MEDIT `.mesh` (ASCII): `MeshVersionFormatted 1|2|3` first, then `Dimension 3`, then sections,
// then `End`. A section keyword is followed by its count (on the same line or the next) and by
// that many entries, ONE ENTRY PER LINE:
//   Vertices    x y z ref         (ref: any integer, ignored)
//   Tetrahedra  a b c d ref       (1-based vertex ids; ref = piece label, an integer >= 0)
// Accepted and ignored when well-formed (right number of values, vertex ids in range):
// Triangles (a b c ref), Quadrilaterals (a b c d ref), Edges (a b ref), Corners, RequiredVertices
// (a vertex id), Ridges, RequiredEdges, RequiredTriangles (an entity id >= 1), Normals and
// Tangents (x y z), NormalAtVertices and TangentAtVertices (vertex id, vector id).
// Vertices must come before every section that names vertices, and appear once; each section
// appears at most once. Hexahedra, Prisms and Pyramids are errors (only tetrahedra are supported);
// so is any other keyword and anything after `End`.
//
// TetGen `.node` + `.ele` (same stem): `.node` starts `<points> 3 <attributes> <markers 0|1>`,
// then `<index> x y z [attributes] [marker]` with consecutive indices from 0 or 1: the first
// index fixes the base of every index in both files. `.ele` starts `<tets> 4 <attributes 0|1>`,
// then `<index> n0 n1 n2 n3 [region]` (consecutive indices); the region attribute, an integral
// number >= 0, is the piece label (0 attributes: every tet is piece 0). Data after the last
// announced entry is an error.
//
// Cracks: one face per line, `a b c`: three 0-based model vertex ids (range checked by
// build_tet_model, which knows the vertex count).
#include <filesystem>

#include "coarse/coarse_model.hpp"

namespace fracref {

/// Reads a MEDIT ASCII `.mesh`. \throw InputError (file:line: cause), also for a missing file.
TetMesh read_medit(const std::filesystem::path& path);

/// Reads TetGen `<stem>.node` and `<stem>.ele`; `path` may name either file or the bare stem.
/// \throw InputError (file:line: cause), also when either file is missing.
TetMesh read_tetgen(const std::filesystem::path& path);

/// Reads a cracks file. \throw InputError (file:line: cause); a file of only comments is no crack.
CrackList read_cracks(const std::filesystem::path& path);

}  // namespace fracref
