#include <cstdint>
#include <limits>
#include <string>

#include "io/ply_format.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref {

std::string_view property_type_name(PropertyType type) {
  switch (type) {
    case PropertyType::Int8: return "char";
    case PropertyType::UInt8: return "uchar";
    case PropertyType::Int16: return "short";
    case PropertyType::UInt16: return "ushort";
    case PropertyType::Int32: return "int";
    case PropertyType::UInt32: return "uint";
    case PropertyType::Float32: return "float";
    case PropertyType::Float64: return "double";
  }
  return "?";
}

namespace io_detail {

bool property_type_from_name(std::string_view name, PropertyType& type) {
  struct Entry { std::string_view a, b; PropertyType t; };
  static constexpr Entry kTypes[] = {
      {"char", "int8", PropertyType::Int8},      {"uchar", "uint8", PropertyType::UInt8},
      {"short", "int16", PropertyType::Int16},   {"ushort", "uint16", PropertyType::UInt16},
      {"int", "int32", PropertyType::Int32},     {"uint", "uint32", PropertyType::UInt32},
      {"float", "float32", PropertyType::Float32}, {"double", "float64", PropertyType::Float64}};
  for (const Entry& e : kTypes) {
    if (name == e.a || name == e.b) {
      type = e.t;
      return true;
    }
  }
  return false;
}

std::size_t property_type_size(PropertyType type) {
  switch (type) {
    case PropertyType::Int8: case PropertyType::UInt8: return 1;
    case PropertyType::Int16: case PropertyType::UInt16: return 2;
    case PropertyType::Int32: case PropertyType::UInt32: case PropertyType::Float32: return 4;
    case PropertyType::Float64: return 8;
  }
  return 0;
}

bool is_integer_type(PropertyType type) {
  return type != PropertyType::Float32 && type != PropertyType::Float64;
}

double property_type_min(PropertyType type) {
  switch (type) {
    case PropertyType::Int8: return std::numeric_limits<std::int8_t>::min();
    case PropertyType::Int16: return std::numeric_limits<std::int16_t>::min();
    case PropertyType::Int32: return std::numeric_limits<std::int32_t>::min();
    case PropertyType::Float32: return std::numeric_limits<float>::lowest();
    case PropertyType::Float64: return std::numeric_limits<double>::lowest();
    default: return 0.0;
  }
}

double property_type_max(PropertyType type) {
  switch (type) {
    case PropertyType::Int8: return std::numeric_limits<std::int8_t>::max();
    case PropertyType::UInt8: return std::numeric_limits<std::uint8_t>::max();
    case PropertyType::Int16: return std::numeric_limits<std::int16_t>::max();
    case PropertyType::UInt16: return std::numeric_limits<std::uint16_t>::max();
    case PropertyType::Int32: return std::numeric_limits<std::int32_t>::max();
    case PropertyType::UInt32: return std::numeric_limits<std::uint32_t>::max();
    case PropertyType::Float32: return std::numeric_limits<float>::max();
    case PropertyType::Float64: return std::numeric_limits<double>::max();
  }
  return 0.0;
}

namespace {

class HeaderParser {
 public:
  HeaderParser(const std::string& file, std::string_view bytes) : file_(file), cursor_(bytes) {}
  PlyHeader parse();

 private:
  void format();
  void element();
  void property();
  PropertyType type(std::string_view name) const;
  void validate() const;
  InputError error(const std::string& what) const { return input_error_at(file_, cursor_.line_number(), what); }

  const std::string& file_;
  LineCursor cursor_;
  std::vector<std::string_view> tokens_;
  PlyHeader header_;
  bool has_format_ = false;
};

PlyHeader HeaderParser::parse() {
  std::string_view line;
  if (!cursor_.next(line) || line != "ply") throw error("not a PLY file (the first line must be 'ply')");
  while (cursor_.next(line)) {
    split_tokens(line, tokens_);
    if (tokens_.empty()) throw error("blank line in the PLY header");
    std::string_view key = tokens_[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      if (tokens_.size() != 1) throw error("end_header line has extra words");
      header_.data_offset = cursor_.offset();
      header_.header_lines = cursor_.line_number();
      validate();
      return std::move(header_);
    }
    if (key == "format") format();
    else if (!has_format_) throw error("the format line must come before " + quote_token(key));
    else if (key == "element") element();
    else if (key == "property") property();
    else throw error("unknown PLY header keyword " + quote_token(key));
  }
  throw error("the header has no end_header line");
}

void HeaderParser::format() {
  if (has_format_) throw error("second format line");
  if (tokens_.size() != 3) throw error("format line needs 'format <encoding> 1.0'");
  std::string_view encoding = tokens_[1];
  if (encoding == "binary_big_endian")
    throw error("format binary_big_endian is not supported (only ascii and binary_little_endian)");
  if (encoding != "ascii" && encoding != "binary_little_endian")
    throw error("unknown PLY format " + quote_token(encoding));
  if (tokens_[2] != "1.0") throw error("unsupported PLY version " + quote_token(tokens_[2]));
  header_.binary = encoding == "binary_little_endian";
  has_format_ = true;
}

void HeaderParser::element() {
  if (tokens_.size() != 3) throw error("element line needs 'element <name> <count>'");
  std::string_view name = tokens_[1];
  if (name != "vertex" && name != "face")
    throw error("unsupported element " + quote_token(name) + " (only vertex and face)");
  for (const PlyElement& e : header_.elements)
    if (e.name == name) throw error("element " + quote_token(name) + " declared twice");
  std::int64_t count = 0;
  std::string why;
  if (!parse_int64(tokens_[2], count, why)) throw error("element count " + quote_token(tokens_[2]) + " " + why);
  if (count < 0) throw error("element count " + quote_token(tokens_[2]) + " is negative");
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw error("element count " + quote_token(tokens_[2]) + " is too large (more than 2^32 - 1)");
  header_.elements.push_back({std::string(name), static_cast<std::size_t>(count), {}});
  if (name == "vertex") header_.vertex_count = static_cast<std::size_t>(count);
}

PropertyType HeaderParser::type(std::string_view name) const {
  PropertyType t{};
  if (!property_type_from_name(name, t)) throw error("unknown property type " + quote_token(name));
  return t;
}

void HeaderParser::property() {
  if (header_.elements.empty()) throw error("property before any element");
  PlyElement& element = header_.elements.back();
  PlyProperty p;
  if (tokens_.size() >= 2 && tokens_[1] == "list") {
    if (tokens_.size() != 5) throw error("list property needs 'property list <count type> <item type> <name>'");
    p.is_list = true;
    p.count_type = type(tokens_[2]);
    p.type = type(tokens_[3]);
    p.name = std::string(tokens_[4]);
    bool index_list = element.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
    if (!index_list)
      throw error("list property " + quote_token(p.name) + " is not supported (only the face index list)");
    if (!is_integer_type(p.count_type) || !is_integer_type(p.type))
      throw error("the face index list needs integer count and item types");
  } else {
    if (tokens_.size() != 3) throw error("property line needs 'property <type> <name>'");
    p.type = type(tokens_[1]);
    p.name = std::string(tokens_[2]);
  }
  for (const PlyProperty& q : element.properties)
    if (q.name == p.name) throw error("property " + quote_token(p.name) + " declared twice in element " + quote_token(element.name));
  if (element.name == "face" && p.is_list)
    for (const PlyProperty& q : element.properties)
      if (q.is_list) throw error("the face element has two index lists");
  element.properties.push_back(std::move(p));
}

void HeaderParser::validate() const {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const PlyElement& e : header_.elements) (e.name == "vertex" ? vertex : face) = &e;
  if (!vertex) throw error("the header declares no vertex element");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const PlyProperty& p : vertex->properties) found = found || p.name == axis;
    if (!found) throw error("the vertex element has no property '" + std::string(axis) + "'");
  }
  if (!face) return;
  bool list = false;
  for (const PlyProperty& p : face->properties) list = list || p.is_list;
  if (!list) throw error("the face element has no vertex_indices list property");
}

}  // namespace

PlyHeader parse_ply_header(const std::string& file, std::string_view bytes) {
  return HeaderParser(file, bytes).parse();
}

}  // namespace io_detail
}  // namespace fracref
