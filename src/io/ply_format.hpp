#pragma once
// Internal: the PLY header model shared by the PLY reader and writer. Not part of the public API.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_soup.hpp"

namespace fracref::io_detail {

struct PlyProperty {
  std::string name;
  PropertyType type = PropertyType::Float64;  ///< the item type for a list
  bool is_list = false;
  PropertyType count_type = PropertyType::UInt8;  ///< lists only
};

struct PlyElement {
  std::string name;  ///< "vertex" or "face"
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool binary = false;  ///< binary_little_endian, else ascii
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;   ///< first byte after the end_header line
  std::size_t header_lines = 0;  ///< lines up to and including end_header
  std::size_t vertex_count = 0;
};

/// Parses and validates the header (see mesh_io.hpp for the accepted subset).
/// \throw InputError "<file>:<line>: <cause>".
PlyHeader parse_ply_header(const std::string& file, std::string_view bytes);

/// The type named `name` (both the classic and the sized PLY names); false if unknown.
bool property_type_from_name(std::string_view name, PropertyType& type);
/// Bytes of one value of `type` in binary PLY.
std::size_t property_type_size(PropertyType type);
bool is_integer_type(PropertyType type);
/// The range of an integer type ([lowest, max] of the float types for Float32/Float64).
double property_type_min(PropertyType type);
double property_type_max(PropertyType type);

}  // namespace fracref::io_detail
