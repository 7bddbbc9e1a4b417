#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {
using namespace io_detail;

class OffParser {
 public:
  OffParser(std::string file, std::string_view text) : file_(std::move(file)), cursor_(skip_utf8_bom(text)), bytes_(text.size()) {}
  MeshSoup parse();

 private:
  bool next_data_line();
  void header();
  std::size_t count(std::string_view token, const char* what) const;
  void vertex();
  void face();
  InputError error(const std::string& what) const { return input_error_at(file_, cursor_.line_number(), what); }
  InputError early_end(std::size_t done, std::size_t announced, const char* what) const;

  std::string file_;
  LineCursor cursor_;
  std::size_t bytes_;
  std::vector<std::string_view> tokens_;
  std::vector<std::uint32_t> corners_;
  MeshSoup soup_;
  std::size_t vertices_ = 0, faces_ = 0;
};

// Skips blank and comment lines; false at the end of the file.
bool OffParser::next_data_line() {
  std::string_view line;
  while (cursor_.next(line)) {
    split_tokens(strip_comment(line), tokens_);
    if (!tokens_.empty()) return true;
  }
  return false;
}

std::size_t OffParser::count(std::string_view token, const char* what) const {
  std::int64_t value = 0;
  std::string why;
  if (!parse_int64(token, value, why)) throw error(std::string(what) + " count " + quote_token(token) + " " + why);
  if (value < 0) throw error(std::string(what) + " count " + quote_token(token) + " is negative");
  if (value > std::numeric_limits<std::uint32_t>::max())
    throw error(std::string(what) + " count " + quote_token(token) + " is too large (more than 2^32 - 1)");
  return static_cast<std::size_t>(value);
}

void OffParser::header() {
  if (!next_data_line()) throw error("file has no OFF header (only comments or blank lines)");
  std::string_view key = tokens_[0];
  if (key != "OFF") {
    if (key.size() > 3 && key.substr(key.size() - 3) == "OFF")
      throw error("OFF variant " + quote_token(key) + " is not supported (only plain OFF)");
    throw error("not an OFF file (the first line must be 'OFF', found " + quote_token(key) + ")");
  }
  if (tokens_.size() > 1 && tokens_[1] == "BINARY") throw error("binary OFF is not supported");
  // The counts usually have their own line; a few writers put them after the keyword.
  if (tokens_.size() > 1) {
    tokens_.erase(tokens_.begin());
  } else if (!next_data_line()) {
    throw error("file ends before the counts line");
  }
  if (tokens_.size() != 3)
    throw error("counts line needs 3 numbers (vertices faces edges), got " + std::to_string(tokens_.size()));
  vertices_ = count(tokens_[0], "vertex");
  faces_ = count(tokens_[1], "face");
  count(tokens_[2], "edge");
}

InputError OffParser::early_end(std::size_t done, std::size_t announced, const char* what) const {
  return error("file ends after " + std::to_string(done) + " of the " + std::to_string(announced) + " " +
               what + " announced in the header");
}

void OffParser::vertex() {
  if (tokens_.size() != 3)
    throw error("vertex needs 3 coordinates, got " + std::to_string(tokens_.size()));
  double xyz[3];
  std::string why;
  for (int i = 0; i < 3; ++i)
    if (!parse_double(tokens_[i], xyz[i], why)) throw error("coordinate " + quote_token(tokens_[i]) + " " + why);
  soup_.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
}

void OffParser::face() {
  std::int64_t n = 0;
  std::string why;
  if (!parse_int64(tokens_[0], n, why)) throw error("face vertex count " + quote_token(tokens_[0]) + " " + why);
  if (n < 3) throw error("face has " + std::to_string(n) + " vertices; a face needs at least 3");
  const std::size_t values = tokens_.size() - 1;
  if (values < static_cast<std::size_t>(n))
    throw error("face announces " + std::to_string(n) + " vertices but lists " + std::to_string(values));
  if (values > static_cast<std::size_t>(n))
    throw error("face announces " + std::to_string(n) + " vertices but has " + std::to_string(values) +
                " values after the count (face colors are not supported)");
  corners_.clear();
  for (std::size_t i = 1; i < tokens_.size(); ++i) {
    std::int64_t index = 0;
    if (!parse_int64(tokens_[i], index, why)) throw error("face index " + quote_token(tokens_[i]) + " " + why);
    if (index < 0) throw error("face index " + std::to_string(index) + " is negative");
    if (index >= static_cast<std::int64_t>(vertices_))
      throw error("face index " + std::to_string(index) + " is out of range (the file has " +
                  std::to_string(vertices_) + " vertices; OFF indices start at 0)");
    corners_.push_back(static_cast<std::uint32_t>(index));
  }
  std::int64_t repeat = first_repeat(corners_.data(), corners_.size());
  if (repeat >= 0) throw error("face repeats vertex " + std::to_string(repeat));
  append_polygon(soup_, corners_.data(), corners_.size());
}

MeshSoup OffParser::parse() {
  header();
  // A hostile header must not make us allocate more than the file could hold.
  soup_.positions.reserve(std::min(vertices_, bytes_ / 6));
  for (std::size_t i = 0; i < vertices_; ++i) {
    if (!next_data_line()) throw early_end(i, vertices_, "vertices");
    vertex();
  }
  soup_.triangles.reserve(std::min(faces_, bytes_ / 8));
  for (std::size_t i = 0; i < faces_; ++i) {
    if (!next_data_line()) throw early_end(i, faces_, "faces");
    face();
  }
  if (next_data_line())
    throw error("extra data after the " + std::to_string(faces_) + " faces announced in the header");
  return std::move(soup_);
}

}  // namespace

MeshSoup read_off(const std::filesystem::path& path) {
  std::string text = read_whole_file(path);
  return OffParser(path.string(), text).parse();
}

}  // namespace fracref
