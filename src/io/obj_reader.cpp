#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {
using namespace io_detail;

constexpr std::int64_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

// "v", "v/vt", "v//vn" or "v/vt/vn" into parts; returns the number of parts, 0 if malformed.
std::size_t split_face_vertex(std::string_view token, std::string_view (&parts)[3]) {
  constexpr auto npos = std::string_view::npos;
  std::size_t s1 = token.find('/');
  parts[0] = token.substr(0, s1);
  if (parts[0].empty()) return 0;
  if (s1 == npos) return 1;
  std::size_t s2 = token.find('/', s1 + 1);
  parts[1] = token.substr(s1 + 1, s2 == npos ? npos : s2 - s1 - 1);
  if (s2 == npos) return parts[1].empty() ? 0 : 2;
  parts[2] = token.substr(s2 + 1);
  return parts[2].empty() || parts[2].find('/') != npos ? 0 : 3;
}

struct PendingFace {
  std::size_t line;
  std::size_t first;  // into ObjParser::corners_
  std::size_t count;
  std::int64_t group;  // into ObjParser::names_, -1 before any o/g
};

// Indices of one kind (v, vt or vn): negative ones are resolved against the count so far,
// positive ones are checked once the whole file is known, at the line that used the largest.
struct IndexKind {
  const char* what;
  std::size_t count = 0;
  std::int64_t max_seen = 0;
  std::size_t max_line = 0;
};

class ObjParser {
 public:
  ObjParser(std::string file, std::string_view text) : file_(std::move(file)), text_(text) {}
  MeshSoup parse();

 private:
  void statement();
  void vertex();
  void reals(const char* what, std::size_t min, std::size_t max, IndexKind& kind);
  void face();
  std::int64_t reference(std::string_view token, std::string_view part, IndexKind& kind);
  void group(std::string_view keyword);
  void smoothing();
  void finish();
  std::int64_t intern(const std::string& name);
  double real(std::string_view token, const char* what) const;
  InputError error(const std::string& what) const { return input_error_at(file_, line_, what); }

  std::string file_;
  std::string_view text_;
  std::string_view raw_;  // the current line without its comment
  std::size_t line_ = 0;
  std::vector<std::string_view> tokens_;
  MeshSoup soup_;
  IndexKind v_{"vertex"}, vt_{"texture coordinate"}, vn_{"normal"};
  std::vector<std::uint32_t> corners_;  // 1-based, resolved
  std::vector<PendingFace> faces_;
  std::vector<std::string> names_;
  std::map<std::string, std::int64_t, std::less<>> name_index_;
  std::int64_t group_ = -1;
};

MeshSoup ObjParser::parse() {
  LineCursor cursor(skip_utf8_bom(text_));
  std::string_view line;
  while (cursor.next(line)) {
    line_ = cursor.line_number();
    raw_ = strip_comment(line);
    split_tokens(raw_, tokens_);
    if (!tokens_.empty()) statement();
  }
  finish();
  return std::move(soup_);
}

void ObjParser::statement() {
  std::string_view key = tokens_[0];
  if (key == "v") vertex();
  else if (key == "vt") reals("texture coordinate", 1, 3, vt_);
  else if (key == "vn") reals("normal", 3, 3, vn_);
  else if (key == "f") face();
  else if (key == "o" || key == "g") group(key);
  else if (key == "s") smoothing();
  else if (key == "usemtl" || key == "mtllib") {
    if (tokens_.size() < 2) throw error(std::string(key) + " needs a name");
  } else if (key == "l" || key == "p") {
    throw error("line/point elements are not supported ('" + std::string(key) + "' statement)");
  } else {
    throw error("unknown OBJ statement " + quote_token(key));
  }
}

double ObjParser::real(std::string_view token, const char* what) const {
  double value = 0.0;
  std::string why;
  if (!parse_double(token, value, why)) throw error(std::string(what) + " " + quote_token(token) + " " + why);
  return value;
}

void ObjParser::vertex() {
  const std::size_t n = tokens_.size() - 1;
  if (n != 3 && n != 4)
    throw error("vertex needs 3 coordinates (or 4 with w = 1), got " + std::to_string(n));
  glm::dvec3 p;
  for (int k = 0; k < 3; ++k) p[k] = real(tokens_[k + 1], "coordinate");  // left to right
  if (n == 4 && real(tokens_[4], "vertex weight") != 1.0)
    throw error("vertex weight w = " + std::string(tokens_[4]) +
                " is not supported (rational vertices); only w = 1 is accepted");
  if (soup_.positions.size() >= static_cast<std::size_t>(kMaxIndex))
    throw error("too many vertices (more than 2^32 - 1)");
  soup_.positions.push_back(p);
  ++v_.count;
}

void ObjParser::reals(const char* what, std::size_t min, std::size_t max, IndexKind& kind) {
  const std::size_t n = tokens_.size() - 1;
  if (n < min || n > max) {
    std::string range = min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max);
    throw error(std::string(what) + " needs " + range + " values, got " + std::to_string(n));
  }
  for (std::size_t i = 1; i <= n; ++i) real(tokens_[i], what);
  ++kind.count;
}

void ObjParser::face() {
  const std::size_t n = tokens_.size() - 1;
  if (n < 3) throw error("face has " + std::to_string(n) + " vertices; a face needs at least 3");
  const std::size_t first = corners_.size();
  for (std::size_t i = 1; i <= n; ++i) {
    std::string_view token = tokens_[i];
    std::string_view parts[3];
    std::size_t count = split_face_vertex(token, parts);
    if (count == 0)
      throw error("face vertex " + quote_token(token) + " is malformed (expected v, v/vt, v//vn or v/vt/vn)");
    corners_.push_back(static_cast<std::uint32_t>(reference(token, parts[0], v_)));
    if (count >= 2 && !parts[1].empty()) reference(token, parts[1], vt_);
    if (count == 3) reference(token, parts[2], vn_);
  }
  std::int64_t repeat = first_repeat(corners_.data() + first, n);
  if (repeat >= 0) throw error("face repeats vertex " + std::to_string(repeat));
  faces_.push_back({line_, first, n, group_});
}

std::int64_t ObjParser::reference(std::string_view token, std::string_view part, IndexKind& kind) {
  std::int64_t index = 0;
  std::string why;
  const auto what = [&] { return std::string(kind.what) + " index "; };  // built only for an error
  if (!parse_int64(part, index, why)) throw error(what() + quote_token(part) + " " + why + " (in " + quote_token(token) + ")");
  if (index == 0) throw error(what() + "0 is invalid (OBJ indices start at 1)");
  if (index < 0) {
    if (-index > static_cast<std::int64_t>(kind.count))
      throw error(what() + std::to_string(index) + " reaches before the first " + kind.what + " (" +
                  std::to_string(kind.count) + " defined so far)");
    return static_cast<std::int64_t>(kind.count) + index + 1;
  }
  if (index > kMaxIndex) throw error(what() + std::to_string(index) + " is out of range");
  if (index > kind.max_seen) {
    kind.max_seen = index;
    kind.max_line = line_;
  }
  return index;
}

void ObjParser::group(std::string_view keyword) {
  std::string_view rest = trim(raw_.substr(raw_.find(keyword) + keyword.size()));
  group_ = intern(rest.empty() ? std::string("default") : std::string(rest));
}

void ObjParser::smoothing() {
  if (tokens_.size() != 2) throw error("'s' needs exactly one argument ('off' or a group number)");
  std::string_view arg = tokens_[1];
  std::int64_t number = 0;
  std::string why;
  if (arg != "off" && arg != "on" && !(parse_int64(arg, number, why) && number >= 0))
    throw error("smoothing group " + quote_token(arg) + " must be 'off' or a non-negative integer");
}

void ObjParser::finish() {
  for (const IndexKind* kind : {&v_, &vt_, &vn_}) {
    if (kind->max_seen > static_cast<std::int64_t>(kind->count))
      throw input_error_at(file_, kind->max_line,
                           std::string(kind->what) + " index " + std::to_string(kind->max_seen) +
                               " is out of range (the file has " + std::to_string(kind->count) + ")");
  }
  bool grouped = false;
  for (const PendingFace& f : faces_) grouped = grouped || f.group >= 0;
  // Faces before the first o/g join the OBJ default group, named "default".
  std::int64_t unnamed = grouped ? intern("default") : -1;
  std::vector<std::int64_t> soup_group(names_.size(), -1);
  std::vector<std::uint32_t> zero_based;
  for (const PendingFace& f : faces_) {
    zero_based.assign(corners_.begin() + f.first, corners_.begin() + f.first + f.count);
    for (std::uint32_t& v : zero_based) --v;
    append_polygon(soup_, zero_based.data(), f.count);
    if (!grouped) continue;
    std::int64_t& slot = soup_group[f.group < 0 ? unnamed : f.group];
    if (slot < 0) {
      slot = static_cast<std::int64_t>(soup_.groups.size());
      soup_.groups.push_back(names_[f.group < 0 ? unnamed : f.group]);
    }
    soup_.triangle_group.resize(soup_.triangles.size(), static_cast<std::uint32_t>(slot));
  }
}

std::int64_t ObjParser::intern(const std::string& name) {
  auto it = name_index_.find(name);
  if (it == name_index_.end()) {
    it = name_index_.emplace(name, static_cast<std::int64_t>(names_.size())).first;
    names_.push_back(name);
  }
  return it->second;
}

}  // namespace

MeshSoup read_obj(const std::filesystem::path& path) {
  std::string text = read_whole_file(path);
  return ObjParser(path.string(), text).parse();
}

}  // namespace fracref
