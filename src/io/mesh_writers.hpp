#pragma once
// Internal: the per-format serializers behind write_mesh. Not part of the public API.
#include <string>

#include "io/mesh_soup.hpp"

namespace fracref::io_detail {

/// Checks what every format needs: indices in range, finite positions, triangle_group empty or
/// one valid entry per triangle. \throw RunError "<file>: cannot write: <cause>".
void check_soup_for_writing(const MeshSoup& soup, const std::string& file);

/// Appends `value` as "%.17g" would print it in the C locale (locale-free, via to_chars).
void append_double(std::string& out, double value);

std::string obj_bytes(const MeshSoup& soup, const std::string& file);
std::string off_bytes(const MeshSoup& soup);
/// \throw RunError when a property column has the wrong length, a bad name, or a value that
///        does not fit its type.
std::string ply_bytes(const MeshSoup& soup, bool binary, const std::string& file);

}  // namespace fracref::io_detail
