// The strict JSON parser: a SAX handler that builds the document itself, so it can see every
// key of every object (to catch duplicates) and the byte position of every error.
#include "scene/json_strict.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <utility>

#include "util/input_size.hpp"

namespace fracref {
namespace {

using nlohmann::json;

/// 1-based line and column of the byte at `index` (index == text.size() means end of input).
std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t index) {
  index = std::min(index, text.size());
  std::size_t line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < index; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return {line, index - line_start + 1};
}

/// The cause in one of nlohmann's messages, without its "[json.exception...] parse error at
/// line L, column C: " preamble (we print our own location).
std::string strip_preamble(const std::string& what) {
  std::string s = what;
  if (s.rfind("[json.exception.", 0) == 0) {
    const auto close = s.find("] ");
    if (close != std::string::npos) s = s.substr(close + 2);
  }
  const auto col = s.find(", column ");
  if (s.rfind("parse error", 0) == 0 && col != std::string::npos) {
    const auto colon = s.find(": ", col);
    if (colon != std::string::npos) s = s.substr(colon + 2);
  }
  return s;
}

class StrictSax {
 public:
  StrictSax(json& root, const std::string& text, const std::string& file)
      : root_(root), text_(text), file_(file) {}

  bool null() { return put(nullptr) != nullptr; }
  bool boolean(bool v) { return put(v) != nullptr; }
  bool number_integer(json::number_integer_t v) { return put(v) != nullptr; }
  bool number_unsigned(json::number_unsigned_t v) { return put(v) != nullptr; }
  bool number_float(json::number_float_t v, const json::string_t&) { return put(v) != nullptr; }
  bool string(json::string_t& v) { return put(std::move(v)) != nullptr; }
  bool binary(json::binary_t& v) { return put(json::binary(v)) != nullptr; }

  bool start_object(std::size_t) {
    check_depth();
    frames_.push_back(Frame{put(json::object()), true, {}, {}});
    return true;
  }
  bool key(json::string_t& k) {
    Frame& f = frames_.back();
    if (!f.keys.insert(k).second) {
      throw InputError(file_ + ": key '" + path_to(k) + "': duplicate key (a key may appear only once per object)");
    }
    f.key = k;
    return true;
  }
  bool end_object() {
    frames_.pop_back();
    return true;
  }
  bool start_array(std::size_t) {
    check_depth();
    frames_.push_back(Frame{put(json::array()), false, {}, {}});
    return true;
  }
  bool end_array() {
    frames_.pop_back();
    return true;
  }

  // `position` counts the bytes read, end of input included. A syntax error is at the last
  // byte read; an overflowing number is reported where it starts.
  bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& ex) {
    const std::size_t back = ex.id == 406 ? token.size() : 1;
    const auto [line, column] = line_column(text_, position >= back ? position - back : 0);
    std::string where = file_ + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
    if (ex.id == 406 && !frames_.empty()) {  // number overflow: name the key being read
      const Frame& f = frames_.back();
      where += "key '" + (f.is_object ? path_to(f.key) : path_to_index(f.node->size())) + "': ";
    }
    if (ex.id == 406) throw InputError(where + strip_preamble(ex.what()) + " (too large for a double)");
    throw InputError(where + strip_preamble(ex.what()));
  }

 private:
  struct Frame {
    json* node;
    bool is_object;
    std::set<std::string> keys;
    std::string key;  // the key whose value comes next
  };

  // A scene is a few levels deep; the code that walks a document (copies, messages that print a
  // value) recurses, and 100,000 nested arrays overflowed its stack.
  static constexpr std::size_t kMaxDepth = 64;
  void check_depth() const {
    if (frames_.size() < kMaxDepth) return;
    const Frame& f = frames_.back();
    const std::string at = f.is_object ? path_to(f.key) : path_to_index(f.node->size());
    throw InputError(file_ + ": key '" + at.substr(0, 120) + (at.size() > 120 ? "..." : "") +
                     "': nested deeper than " + std::to_string(kMaxDepth) + " levels");
  }

  json* put(json value) {
    if (frames_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& f = frames_.back();
    if (f.is_object) return &((*f.node)[f.key] = std::move(value));
    f.node->push_back(std::move(value));
    return &f.node->back();
  }

  std::string prefix() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (f.is_object) {
        if (!p.empty()) p += '.';
        p += f.key;
      } else {
        p += '[';
        p += std::to_string(f.node->size() - 1);  // the open element is the last
        p += ']';
      }
    }
    return p;
  }
  std::string path_to(const std::string& k) const {
    const std::string p = prefix();
    return p.empty() ? k : p + "." + k;
  }
  std::string path_to_index(std::size_t i) const { return prefix() + "[" + std::to_string(i) + "]"; }

  json& root_;
  const std::string& text_;
  const std::string& file_;
  std::vector<Frame> frames_;
};

}  // namespace

nlohmann::json parse_json_strict(const std::string& text, const std::string& filename) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(filename + ": the file is empty (expected a JSON object)");
  }
  json root;
  StrictSax sax(root, text, filename);
  json::sax_parse(text, &sax, json::input_format_t::json, /*strict=*/true);
  return root;
}

nlohmann::json read_json_file(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  const std::string name = path.string();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw InputError(name + ": file not found");
  if (fs::is_directory(st)) throw InputError(name + ": is a folder, expected a JSON file");
  if (fs::is_regular_file(st)) check_input_file_size(path, fs::file_size(path, ec));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open: " + std::strerror(errno));
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(name + ": read error");
  return parse_json_strict(text, name);
}

}  // namespace fracref
