#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>

#include "io/mesh_writers.hpp"
#include "io/ply_format.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref::io_detail {
namespace {

template <typename T>
void store_le(std::string& out, T value) {
  using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
            std::conditional_t<sizeof(T) == 2, std::uint16_t,
            std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  U u = std::bit_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) out += static_cast<char>((u >> (8 * i)) & 0xff);
}

// `value` has already been checked to fit `type`, so every cast below is exact.
void store_binary(std::string& out, PropertyType type, double value) {
  switch (type) {
    case PropertyType::Int8: store_le(out, static_cast<std::int8_t>(value)); break;
    case PropertyType::UInt8: store_le(out, static_cast<std::uint8_t>(value)); break;
    case PropertyType::Int16: store_le(out, static_cast<std::int16_t>(value)); break;
    case PropertyType::UInt16: store_le(out, static_cast<std::uint16_t>(value)); break;
    case PropertyType::Int32: store_le(out, static_cast<std::int32_t>(value)); break;
    case PropertyType::UInt32: store_le(out, static_cast<std::uint32_t>(value)); break;
    case PropertyType::Float32: store_le(out, static_cast<float>(value)); break;
    case PropertyType::Float64: store_le(out, value); break;
  }
}

void store_ascii(std::string& out, PropertyType type, double value) {
  if (is_integer_type(type)) out += std::to_string(static_cast<std::int64_t>(value));
  else append_double(out, value);
}

void check_columns(const std::vector<PropertyColumn>& columns, std::size_t rows, const char* element,
                   std::set<std::string> taken, const std::string& file) {
  const std::string prefix = file + ": cannot write: " + element + " property ";
  for (const PropertyColumn& c : columns) {
    bool bad_name = c.name.empty() || c.name.find_first_of(" \t\r\n\v\f") != std::string::npos;
    if (bad_name || !taken.insert(c.name).second)
      throw RunError(prefix + quote_token(c.name) + ": the name is empty, has blanks or is already used");
    if (c.values.size() != rows)
      throw RunError(prefix + quote_token(c.name) + " has " + std::to_string(c.values.size()) + " values for " +
                     std::to_string(rows) + " " + element + "s");
    for (double v : c.values) {
      bool fits = std::isfinite(v) && v >= property_type_min(c.type) && v <= property_type_max(c.type) &&
                  (!is_integer_type(c.type) || std::trunc(v) == v);
      if (!fits)
        throw RunError(prefix + quote_token(c.name) + ": value " + std::to_string(v) + " does not fit " +
                       std::string(property_type_name(c.type)));
    }
  }
}

std::string header(const MeshSoup& soup, bool binary, PropertyType index_type) {
  std::string h = "ply\nformat ";
  h += binary ? "binary_little_endian" : "ascii";
  h += " 1.0\ncomment written by fracref\nelement vertex " + std::to_string(soup.positions.size()) +
       "\nproperty double x\nproperty double y\nproperty double z\n";
  for (const PropertyColumn& c : soup.vertex_properties)
    h += "property " + std::string(property_type_name(c.type)) + " " + c.name + "\n";
  h += "element face " + std::to_string(soup.triangles.size()) + "\nproperty list uchar " +
       std::string(property_type_name(index_type)) + " vertex_indices\n";
  for (const PropertyColumn& c : soup.face_properties)
    h += "property " + std::string(property_type_name(c.type)) + " " + c.name + "\n";
  return h + "end_header\n";
}

// One element row: `fixed` values first (positions or indices), then the extra columns.
void append_row(std::string& out, bool binary, const double* fixed, std::size_t n_fixed, PropertyType fixed_type,
                bool list, const std::vector<PropertyColumn>& columns, std::size_t row) {
  if (binary) {
    if (list) store_le(out, static_cast<std::uint8_t>(n_fixed));
    for (std::size_t i = 0; i < n_fixed; ++i) store_binary(out, fixed_type, fixed[i]);
    for (const PropertyColumn& c : columns) store_binary(out, c.type, c.values[row]);
    return;
  }
  if (list) out += std::to_string(n_fixed) + " ";
  for (std::size_t i = 0; i < n_fixed; ++i) {
    if (i > 0) out += ' ';
    store_ascii(out, fixed_type, fixed[i]);
  }
  for (const PropertyColumn& c : columns) {
    out += ' ';
    store_ascii(out, c.type, c.values[row]);
  }
  out += '\n';
}

}  // namespace

std::string ply_bytes(const MeshSoup& soup, bool binary, const std::string& file) {
  check_columns(soup.vertex_properties, soup.positions.size(), "vertex", {"x", "y", "z"}, file);
  check_columns(soup.face_properties, soup.triangles.size(), "face", {"vertex_indices", "vertex_index"}, file);
  const bool small = soup.positions.size() <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
  const PropertyType index_type = small ? PropertyType::Int32 : PropertyType::UInt32;
  std::string out = header(soup, binary, index_type);
  for (std::size_t i = 0; i < soup.positions.size(); ++i) {
    const double xyz[3] = {soup.positions[i].x, soup.positions[i].y, soup.positions[i].z};
    append_row(out, binary, xyz, 3, PropertyType::Float64, false, soup.vertex_properties, i);
  }
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const double v[3] = {double(soup.triangles[t][0]), double(soup.triangles[t][1]), double(soup.triangles[t][2])};
    append_row(out, binary, v, 3, index_type, true, soup.face_properties, t);
  }
  return out;
}

}  // namespace fracref::io_detail
