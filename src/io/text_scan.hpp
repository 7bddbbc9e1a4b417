#pragma once
// Internal helpers shared by the strict mesh readers: whole-file reading, line and token
// scanning, locale-free number parsing and fan triangulation. Not part of the public API.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_soup.hpp"
#include "util/error.hpp"

namespace fracref::io_detail {

/// The bytes of `path`.
/// \throw InputError "<file>: ..." when the file is missing, a folder, unreadable or empty, or
///        larger than max_input_file_bytes() (checked before reading).
std::string read_whole_file(const std::filesystem::path& path);

/// `text` without a leading UTF-8 byte order mark (some Windows tools write one into OBJ/OFF).
std::string_view skip_utf8_bom(std::string_view text);

/// Walks `text` line by line; "\r\n" and "\n" both end a line (the '\r' is dropped).
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  /// The next line into `line`; false at the end of the text. Line numbers start at 1.
  bool next(std::string_view& line);
  std::size_t line_number() const { return line_; }
  /// Byte offset of the first byte after the current line (its '\n' included).
  std::size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

/// Splits `line` at blanks (space, tab, '\r', '\v', '\f') into `out` (cleared first).
void split_tokens(std::string_view line, std::vector<std::string_view>& out);

/// `line` without the first '#' and what follows it.
std::string_view strip_comment(std::string_view line);

/// `line` without leading and trailing blanks.
std::string_view trim(std::string_view line);

/// "'token'" for messages, shortened when long and with control bytes escaped.
std::string quote_token(std::string_view token);

/// Parses a finite double with std::from_chars (one leading '+' allowed, nothing trailing).
/// On failure returns false and sets `why` to the cause without the token, e.g. "is not finite".
bool parse_double(std::string_view token, double& out, std::string& why);

/// Parses a decimal integer (no '+', nothing trailing). On failure sets `why` like parse_double.
bool parse_int64(std::string_view token, std::int64_t& out, std::string& why);

/// "<file>: byte <offset>: <what>" — located errors in binary data.
InputError input_error_at_byte(const std::string& file, std::size_t offset, const std::string& what);

/// Appends polygon `v[0..n)` (n >= 3, 0-based) as n-2 triangles and counts it in `polygons` /
/// `polygons_triangulated`: triangulated in its own plane (triangulate_polygon) when every corner
/// is already in soup.positions, else as the fan (v0, vi, vi+1).
void append_polygon(MeshSoup& soup, const std::uint32_t* v, std::size_t n);

/// The first repeated value of `v[0..n)`, or -1 when all differ.
std::int64_t first_repeat(const std::uint32_t* v, std::size_t n);

}  // namespace fracref::io_detail
