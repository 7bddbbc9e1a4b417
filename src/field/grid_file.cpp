#include "field/grid_file.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "util/atomic_output.hpp"
#include "util/error.hpp"
#include "util/input_size.hpp"

namespace fracref {
namespace {

constexpr unsigned kMaxDim = 1024;

std::string read_bytes(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError(file.string() + ": cannot read the strength grid file (missing or not a file)");
  check_input_file_size(file, std::filesystem::file_size(file, ec));
  std::ifstream in(file, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in) throw InputError(file.string() + ": cannot read the strength grid file");
  return ss.str();
}

// A NUL byte is not a blank (strchr would find the terminator): it stays in a token, which then
// fails to parse, and every byte is consumed.
bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> tokens(std::string_view line) {
  line = line.substr(0, line.find('#'));
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !blank(line[j])) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string quoted(std::string_view t) { return "'" + std::string(t.substr(0, 40)) + (t.size() > 40 ? "...'" : "'"); }

// A finite double, locale-free, nothing trailing; why = the cause on failure.
bool parse_number(std::string_view t, double& v, std::string& why) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range) return why = "is out of range", false;
  if (ec != std::errc() || p != t.data() + t.size()) return why = "is not a number", false;
  if (!std::isfinite(v)) return why = "is not finite", false;
  return true;
}

// The header, key by key; `line` is the current line number for messages.
struct Header {
  std::optional<glm::uvec3> dims;
  std::optional<glm::dvec3> origin;
  std::optional<double> cell;
  std::optional<bool> binary;
};

void parse_key(const std::string& f, std::size_t line, const std::vector<std::string_view>& tk, Header& h) {
  const std::string_view key = tk[0];
  auto want = [&](std::size_t n) {
    if (tk.size() != n + 1)
      throw input_error_at(f, line, "key '" + std::string(key) + "' takes " + std::to_string(n) + " value(s), got " +
                                        std::to_string(tk.size() - 1));
  };
  auto num = [&](std::size_t i) {
    double v;
    std::string why;
    if (!parse_number(tk[i], v, why)) throw input_error_at(f, line, "key '" + std::string(key) + "': " + quoted(tk[i]) + " " + why);
    return v;
  };
  auto repeated = [&](bool set) {
    if (set) throw input_error_at(f, line, "key '" + std::string(key) + "' is given twice");
  };
  if (key == "dims") {
    repeated(h.dims.has_value()), want(3);
    glm::uvec3 d;
    for (int i = 0; i < 3; ++i) {
      double v = num(i + 1);
      if (v != std::floor(v) || v < 2 || v > kMaxDim)
        throw input_error_at(f, line, "key 'dims': " + quoted(tk[i + 1]) + " must be an integer in [2, 1024]");
      d[i] = unsigned(v);
    }
    h.dims = d;
  } else if (key == "origin") {
    repeated(h.origin.has_value()), want(3);
    h.origin = glm::dvec3(num(1), num(2), num(3));
  } else if (key == "cell") {
    repeated(h.cell.has_value()), want(1);
    double c = num(1);
    if (!(c > 0)) throw input_error_at(f, line, "key 'cell': " + quoted(tk[1]) + " must be > 0");
    h.cell = c;
  } else if (key == "format") {
    repeated(h.binary.has_value()), want(1);
    if (tk[1] != "float32-le" && tk[1] != "text")
      throw input_error_at(f, line, "key 'format': " + quoted(tk[1]) + " is not 'float32-le' or 'text'");
    h.binary = tk[1] == "float32-le";
  } else {
    throw input_error_at(f, line, "unknown key " + quoted(key) + " (dims, origin, cell, format, end_header)");
  }
}

// Splits off the next line of `text` from `pos`; false at the end.
bool next_line(std::string_view text, std::size_t& pos, std::string_view& line) {
  if (pos >= text.size()) return false;
  std::size_t e = text.find('\n', pos);
  line = text.substr(pos, (e == std::string_view::npos ? text.size() : e) - pos);
  pos = e == std::string_view::npos ? text.size() : e + 1;
  return true;
}

void read_binary(const std::string& f, std::string_view data, std::size_t offset, Grid3& g) {
  const std::size_t want = g.size() * 4;
  if (data.size() < want)
    throw InputError(f + ": byte " + std::to_string(offset + data.size()) + ": truncated binary data: " +
                     std::to_string(data.size()) + " bytes for " + std::to_string(g.size()) + " float32 values (" +
                     std::to_string(want) + " bytes needed)");
  if (data.size() > want)
    throw InputError(f + ": byte " + std::to_string(offset + want) + ": " + std::to_string(data.size() - want) +
                     " trailing bytes after the " + std::to_string(g.size()) + " values");
  g.values.resize(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto* b = reinterpret_cast<const unsigned char*>(data.data() + 4 * i);
    std::uint32_t u = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
    float v = std::bit_cast<float>(u);
    if (!std::isfinite(v))
      throw InputError(f + ": byte " + std::to_string(offset + 4 * i) + ": value " + std::to_string(i) + " is not finite");
    g.values[i] = v;
  }
}

void read_text(const std::string& f, std::string_view text, std::size_t pos, std::size_t line_no, Grid3& g) {
  // At most one value per two bytes left: a header announcing 1024^3 values over a few bytes of
  // text must not reserve 4 GB.
  g.values.reserve(std::min(g.size(), (text.size() - pos) / 2 + 1));
  std::string_view line;
  while (next_line(text, pos, line)) {
    ++line_no;
    for (std::string_view t : tokens(line)) {
      if (g.values.size() == g.size())
        throw input_error_at(f, line_no, "too many values: " + quoted(t) + " after the " + std::to_string(g.size()) + " of dims");
      double v;
      std::string why;
      if (!parse_number(t, v, why)) throw input_error_at(f, line_no, "value " + quoted(t) + " " + why);
      if (std::abs(v) > std::numeric_limits<float>::max())
        throw input_error_at(f, line_no, "value " + quoted(t) + " is out of float range");
      g.values.push_back(float(v));
    }
  }
  if (g.values.size() != g.size())
    throw input_error_at(f, line_no, "too few values: " + std::to_string(g.values.size()) + " of the " +
                                         std::to_string(g.size()) + " that dims give");
}

}  // namespace

Grid3 read_strength_grid(const std::filesystem::path& file) {
  const std::string f = file.string();
  const std::string bytes = read_bytes(file);
  std::string_view text(bytes);
  std::size_t pos = 0, line_no = 0;
  std::string_view line;
  if (!next_line(text, pos, line) || tokens(line) != std::vector<std::string_view>{"fracref-grid", "1"})
    throw input_error_at(f, 1, "not a strength grid: the first line must be 'fracref-grid 1'");
  line_no = 1;
  Header h;
  bool ended = false;
  while (!ended && next_line(text, pos, line)) {
    ++line_no;
    std::vector<std::string_view> tk = tokens(line);
    if (tk.empty()) continue;
    if (tk[0] == "end_header") {
      if (tk.size() != 1) throw input_error_at(f, line_no, "'end_header' takes no value");
      ended = true;
    } else {
      parse_key(f, line_no, tk, h);
    }
  }
  if (!ended) throw input_error_at(f, line_no, "the header has no 'end_header' line");
  for (auto [set, key] : {std::pair{h.dims.has_value(), "dims"}, {h.origin.has_value(), "origin"},
                          {h.cell.has_value(), "cell"}, {h.binary.has_value(), "format"}})
    if (!set) throw input_error_at(f, line_no, std::string("missing key '") + key + "' before 'end_header'");
  Grid3 g;
  g.dims = *h.dims;
  g.origin = *h.origin;
  g.cell = *h.cell;
  if (*h.binary)
    read_binary(f, text.substr(pos), pos, g);
  else
    read_text(f, text, pos, line_no, g);
  return g;
}

Grid3 load_strength_grid(const std::filesystem::path& file, const glm::dvec3& lo, const glm::dvec3& hi,
                         const glm::uvec3& resolution) {
  Grid3 g = read_strength_grid(file);
  auto box = [](const glm::dvec3& a, const glm::dvec3& b) {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << std::setprecision(6) << "[" << a.x << ", " << a.y << ", " << a.z << "] .. [" << b.x << ", " << b.y << ", " << b.z << "]";
    return s.str();
  };
  auto dims = [](const glm::uvec3& d) {
    return std::to_string(d.x) + " " + std::to_string(d.y) + " " + std::to_string(d.z);
  };
  if (resolution != glm::uvec3(0) && resolution != g.dims)
    throw InputError(file.string() + ": dims " + dims(g.dims) + " differ from the scene's field.resolution " + dims(resolution) +
                     " (leave field.resolution out for a grid field)");
  const glm::dvec3 top = g.origin + g.cell * glm::dvec3(g.dims - glm::uvec3(1));
  const double eps = 1e-9 * glm::length(hi - lo);
  for (int a = 0; a < 3; ++a)
    if (g.origin[a] > lo[a] + eps || top[a] < hi[a] - eps)
      throw InputError(file.string() + ": the grid covers " + box(g.origin, top) + " but the exterior's bounding box is " +
                       box(lo, hi) + ": the strength grid must cover the exterior");
  return g;
}

void write_strength_grid(const std::filesystem::path& file, const Grid3& grid, bool binary) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(17) << "fracref-grid 1\ndims " << grid.dims.x << " " << grid.dims.y << " " << grid.dims.z
      << "\norigin " << grid.origin.x << " " << grid.origin.y << " " << grid.origin.z << "\ncell " << grid.cell
      << "\nformat " << (binary ? "float32-le" : "text") << "\nend_header\n";
  std::string bytes = out.str();
  if (binary) {
    for (float v : grid.values) {
      std::uint32_t u = std::bit_cast<std::uint32_t>(v);
      for (int s = 0; s < 32; s += 8) bytes.push_back(char((u >> s) & 0xff));
    }
  } else {
    std::ostringstream t;
    t.imbue(std::locale::classic());
    t << std::setprecision(9);
    for (std::size_t i = 0; i < grid.values.size(); ++i)
      t << grid.values[i] << ((i + 1) % grid.dims.x == 0 ? '\n' : ' ');
    bytes += t.str();
  }
  write_file_atomic(file, bytes);
}

}  // namespace fracref
