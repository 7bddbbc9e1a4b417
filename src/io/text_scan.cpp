#include "io/text_scan.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "io/polygon_triangulation.hpp"
#include "util/input_size.hpp"

namespace fracref::io_detail {
namespace fs = std::filesystem;

std::string read_whole_file(const fs::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  auto status = fs::status(path, ec);
  if (ec || !fs::exists(status)) throw InputError(name + ": cannot open: no such file");
  if (fs::is_directory(status)) throw InputError(name + ": cannot open: it is a directory");
  if (fs::is_regular_file(status)) check_input_file_size(path, fs::file_size(path, ec));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open for reading: " + std::strerror(errno));
  std::string text;
  // Read at once when the size is known (a stream's copy was a tenth of an OBJ's read); a pipe
  // or another file without one is read through the stream.
  const std::streamoff size = in.seekg(0, std::ios::end) ? std::streamoff(in.tellg()) : std::streamoff(-1);
  if (size >= 0 && in.seekg(0, std::ios::beg)) {
    text.resize(std::size_t(size));
    in.read(text.data(), size);
    text.resize(std::size_t(in.gcount()));
  } else {
    in.clear();
    std::ostringstream bytes;
    bytes << in.rdbuf();
    text = std::move(bytes).str();
  }
  if (in.bad()) throw InputError(name + ": read error: " + std::strerror(errno));
  if (text.empty()) throw InputError(name + ": file is empty");
  return text;
}

std::string_view skip_utf8_bom(std::string_view text) {
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  return text.substr(0, 3) == kBom ? text.substr(3) : text;
}

bool LineCursor::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  std::size_t end = text_.find('\n', pos_);
  std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++line_;
  return true;
}

namespace {
// Compared directly, not by searching a string of blanks per character (memchr): this runs for
// every character of every mesh file, and the search's call cost showed in reading large OBJs.
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
}  // namespace

void split_tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

std::string_view strip_comment(std::string_view line) {
  std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

std::string_view trim(std::string_view line) {
  while (!line.empty() && is_blank(line.front())) line.remove_prefix(1);
  while (!line.empty() && is_blank(line.back())) line.remove_suffix(1);
  return line;
}

std::string quote_token(std::string_view token) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    unsigned char c = static_cast<unsigned char>(token[i]);
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (token.size() > kMax) out += "...";
  return out + "'";
}

namespace {
// The cause when from_chars stopped early: a comma gets its own hint because European locales
// write decimals that way and the file would otherwise be misread digit by digit.
std::string trailing_cause(std::string_view token, std::size_t used) {
  if (token.find(',') != std::string_view::npos)
    return "is not a number (comma used as decimal separator?)";
  if (used == 0) return "is not a number";
  return "is not a number (trailing " + quote_token(token.substr(used)) + ")";
}
}  // namespace

bool parse_double(std::string_view token, double& out, std::string& why) {
  std::string_view digits = token;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+')
    digits.remove_prefix(1);
  const char* first = digits.data();
  const char* last = first + digits.size();
  auto [ptr, ec] = std::from_chars(first, last, out, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) {
    why = "is out of the range of double (overflow or underflow)";
    return false;
  }
  if (ec != std::errc() || ptr != last) {
    why = trailing_cause(token, ec != std::errc() ? 0 : static_cast<std::size_t>(ptr - first));
    return false;
  }
  if (!std::isfinite(out)) {
    why = "is not finite";
    return false;
  }
  return true;
}

bool parse_int64(std::string_view token, std::int64_t& out, std::string& why) {
  const char* first = token.data();
  const char* last = first + token.size();
  auto [ptr, ec] = std::from_chars(first, last, out, 10);
  if (ec == std::errc::result_out_of_range) {
    why = "is out of the range of a 64-bit integer";
    return false;
  }
  if (ec != std::errc() || ptr != last) {
    why = "is not an integer";
    return false;
  }
  return true;
}

InputError input_error_at_byte(const std::string& file, std::size_t offset, const std::string& what) {
  return InputError(file + ": byte " + std::to_string(offset) + ": " + what);
}

void append_polygon(MeshSoup& soup, const std::uint32_t* v, std::size_t n) {
  const auto polygon = static_cast<std::uint32_t>(soup.polygons);
  // A polygon whose corners are all read already is triangulated in its plane; one naming a
  // vertex further on (OBJ allows it, rarely) is fanned.
  bool known = n > 3;
  for (std::size_t i = 0; known && i < n; ++i) known = v[i] < soup.positions.size();
  if (known) {
    triangulate_polygon(soup.positions, v, n, soup.triangles);
  } else {
    for (std::size_t i = 1; i + 1 < n; ++i) soup.triangles.push_back({v[0], v[i], v[i + 1]});
  }
  soup.triangle_polygon.resize(soup.triangles.size(), polygon);
  ++soup.polygons;
  if (n > 3) ++soup.polygons_triangulated;
}

std::int64_t first_repeat(const std::uint32_t* v, std::size_t n) {
  if (n <= 16) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if (v[i] == v[j]) return v[i];
    return -1;
  }
  std::vector<std::uint32_t> sorted(v, v + n);
  std::sort(sorted.begin(), sorted.end());
  auto it = std::adjacent_find(sorted.begin(), sorted.end());
  return it == sorted.end() ? -1 : static_cast<std::int64_t>(*it);
}

}  // namespace fracref::io_detail
