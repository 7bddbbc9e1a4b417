#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.hpp"
#include "io/ply_format.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {
using namespace io_detail;

// Values of one element instance at a time, from ASCII lines or little-endian bytes; errors
// name the element, its index and the line or byte offset of the value in hand.
class ValueSource {
 public:
  ValueSource(const std::string& file) : file_(file) {}
  virtual ~ValueSource() = default;
  virtual void begin(const PlyElement& element, std::size_t index) = 0;
  virtual double next(PropertyType type, const PlyProperty& property) = 0;
  virtual void end() = 0;
  virtual void finish() = 0;
  /// "<file>:<line>: " or "<file>: byte <offset>: " then "<element> <index>: <what>".
  virtual InputError error(const std::string& what) const = 0;

 protected:
  std::string subject() const { return element_->name + " " + std::to_string(index_); }
  std::string about(const PlyProperty& p) const { return subject() + ", property '" + p.name + "': "; }

  const std::string& file_;
  const PlyElement* element_ = nullptr;
  std::size_t index_ = 0;
};

class AsciiSource final : public ValueSource {
 public:
  AsciiSource(const std::string& file, std::string_view data, std::size_t first_line)
      : ValueSource(file), cursor_(data), first_line_(first_line) {}

  void begin(const PlyElement& element, std::size_t index) override {
    element_ = &element;
    index_ = index;
    if (!next_line())
      throw input_error_at(file_, line(), "file ends after " + std::to_string(index) + " of the " +
                           std::to_string(element.count) + " " + element.name +
                           " elements announced in the header");
    pos_ = 0;
  }

  double next(PropertyType type, const PlyProperty& property) override {
    if (pos_ >= tokens_.size())
      throw error("has too few values for the properties the header declares");
    std::string_view token = tokens_[pos_++];
    std::string why;
    if (is_integer_type(type)) {
      std::int64_t v = 0;
      if (!parse_int64(token, v, why)) throw value_error(property, token, why);
      if (v < property_type_min(type) || v > property_type_max(type))
        throw value_error(property, token, "does not fit " + std::string(property_type_name(type)));
      return static_cast<double>(v);
    }
    double v = 0.0;
    if (!parse_double(token, v, why)) throw value_error(property, token, why);
    if (type == PropertyType::Float32 && std::fabs(v) > property_type_max(type))
      throw value_error(property, token, "overflows float");
    return v;
  }

  void end() override {
    if (pos_ != tokens_.size())
      throw error("has " + std::to_string(tokens_.size() - pos_) + " values more than the header declares");
  }

  void finish() override {
    if (next_line()) throw input_error_at(file_, line(), "extra data after the last element announced in the header");
  }

  InputError error(const std::string& what) const override {
    return input_error_at(file_, line(), subject() + " " + what);
  }

 private:
  std::size_t line() const { return first_line_ + cursor_.line_number(); }
  bool next_line() {
    std::string_view text;
    while (cursor_.next(text)) {
      split_tokens(text, tokens_);
      if (!tokens_.empty()) return true;
    }
    return false;
  }
  InputError value_error(const PlyProperty& p, std::string_view token, const std::string& why) const {
    return input_error_at(file_, line(), about(p) + "value " + quote_token(token) + " " + why);
  }

  LineCursor cursor_;
  std::size_t first_line_;
  std::vector<std::string_view> tokens_;
  std::size_t pos_ = 0;
};

template <typename T>
T load_le(const unsigned char* p) {
  using U = std::conditional_t<sizeof(T) == 1, std::uint8_t,
            std::conditional_t<sizeof(T) == 2, std::uint16_t,
            std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  U u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) u |= static_cast<U>(U(p[i]) << (8 * i));
  return std::bit_cast<T>(u);
}

class BinarySource final : public ValueSource {
 public:
  BinarySource(const std::string& file, std::string_view bytes, std::size_t offset)
      : ValueSource(file), bytes_(bytes), pos_(offset) {}

  void begin(const PlyElement& element, std::size_t index) override {
    element_ = &element;
    index_ = index;
  }

  double next(PropertyType type, const PlyProperty& property) override {
    value_at_ = pos_;
    std::size_t size = property_type_size(type);
    if (bytes_.size() - pos_ < size)
      throw input_error_at_byte(file_, bytes_.size(), "file ends inside " + subject() + " (truncated)");
    const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data() + pos_);
    pos_ += size;
    double v = decode(type, p);
    if (!std::isfinite(v)) throw input_error_at_byte(file_, value_at_, about(property) + "value " + std::to_string(v) + " is not finite");
    return v;
  }

  void end() override {}

  void finish() override {
    if (pos_ != bytes_.size())
      throw input_error_at_byte(file_, pos_, std::to_string(bytes_.size() - pos_) +
                                " bytes of extra data after the last element announced in the header");
  }

  InputError error(const std::string& what) const override {
    return input_error_at_byte(file_, value_at_, subject() + " " + what);
  }

 private:
  static double decode(PropertyType type, const unsigned char* p) {
    switch (type) {
      case PropertyType::Int8: return load_le<std::int8_t>(p);
      case PropertyType::UInt8: return load_le<std::uint8_t>(p);
      case PropertyType::Int16: return load_le<std::int16_t>(p);
      case PropertyType::UInt16: return load_le<std::uint16_t>(p);
      case PropertyType::Int32: return load_le<std::int32_t>(p);
      case PropertyType::UInt32: return load_le<std::uint32_t>(p);
      case PropertyType::Float32: return load_le<float>(p);
      case PropertyType::Float64: return load_le<double>(p);
    }
    return 0.0;
  }

  std::string_view bytes_;
  std::size_t pos_;
  std::size_t value_at_ = 0;
};

class PlyReader {
 public:
  PlyReader(const PlyHeader& header, ValueSource& source) : header_(header), src_(source) {}
  MeshSoup read(std::size_t data_bytes);

 private:
  void vertex(const PlyElement& e);
  void face(const PlyElement& e);

  const PlyHeader& header_;
  ValueSource& src_;
  MeshSoup soup_;
  std::vector<std::uint32_t> corners_;
  std::vector<double> face_values_;
};

MeshSoup PlyReader::read(std::size_t data_bytes) {
  for (const PlyElement& e : header_.elements) {
    bool is_vertex = e.name == "vertex";
    auto& columns = is_vertex ? soup_.vertex_properties : soup_.face_properties;
    for (const PlyProperty& p : e.properties) {
      bool xyz = is_vertex && (p.name == "x" || p.name == "y" || p.name == "z");
      if (!xyz && !p.is_list) columns.push_back({p.name, p.type, {}});
    }
    // A hostile header must not make us allocate more than the file could hold.
    std::size_t plausible = std::min(e.count, data_bytes / 2);
    if (is_vertex) soup_.positions.reserve(plausible);
    for (std::size_t i = 0; i < e.count; ++i) {
      src_.begin(e, i);
      is_vertex ? vertex(e) : face(e);
      src_.end();
    }
  }
  src_.finish();
  return std::move(soup_);
}

void PlyReader::vertex(const PlyElement& e) {
  glm::dvec3 p(0.0);
  std::size_t column = 0;
  for (const PlyProperty& prop : e.properties) {
    double v = src_.next(prop.type, prop);
    if (prop.name == "x") p.x = v;
    else if (prop.name == "y") p.y = v;
    else if (prop.name == "z") p.z = v;
    else soup_.vertex_properties[column++].values.push_back(v);
  }
  soup_.positions.push_back(p);
}

void PlyReader::face(const PlyElement& e) {
  face_values_.clear();
  corners_.clear();
  for (const PlyProperty& prop : e.properties) {
    if (!prop.is_list) {
      face_values_.push_back(src_.next(prop.type, prop));
      continue;
    }
    double n = src_.next(prop.count_type, prop);
    if (n < 3) throw src_.error("has " + std::to_string(static_cast<std::int64_t>(n)) + " vertices; a face needs at least 3");
    for (double k = 0; k < n; ++k) {
      double index = src_.next(prop.type, prop);
      if (index < 0) throw src_.error("vertex index " + std::to_string(static_cast<std::int64_t>(index)) + " is negative");
      if (index >= static_cast<double>(header_.vertex_count))
        throw src_.error("vertex index " + std::to_string(static_cast<std::int64_t>(index)) +
                         " is out of range (the header declares " + std::to_string(header_.vertex_count) + " vertices)");
      corners_.push_back(static_cast<std::uint32_t>(index));
    }
  }
  std::int64_t repeat = first_repeat(corners_.data(), corners_.size());
  if (repeat >= 0) throw src_.error("repeats vertex " + std::to_string(repeat));
  append_polygon(soup_, corners_.data(), corners_.size());
  for (std::size_t c = 0; c < face_values_.size(); ++c)
    soup_.face_properties[c].values.resize(soup_.triangles.size(), face_values_[c]);
}

}  // namespace

MeshSoup read_ply(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::string bytes = read_whole_file(path);
  PlyHeader header = parse_ply_header(file, bytes);
  std::string_view data = std::string_view(bytes).substr(header.data_offset);
  if (header.binary) {
    BinarySource source(file, bytes, header.data_offset);
    return PlyReader(header, source).read(data.size());
  }
  AsciiSource source(file, data, header.header_lines);
  return PlyReader(header, source).read(data.size());
}

}  // namespace fracref
