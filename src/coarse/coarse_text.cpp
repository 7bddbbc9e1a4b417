// Located token scanning for the coarse readers.
#include <cstdint>
#include <cstdio>
#include <limits>

#include "coarse/coarse_internal.hpp"

namespace fracref::coarse_detail {
using namespace io_detail;

std::string quote(std::string_view token) {
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += char(c);
    }
  }
  return out + (token.size() > 40 ? "...'" : "'");
}

bool TokenLines::next() {
  std::string_view line;
  while (cursor_.next(line)) {
    split_tokens(strip_comment(line), tokens_);
    if (!tokens_.empty()) return true;
  }
  tokens_.clear();
  return false;
}

std::int64_t TokenLines::integer(std::string_view token, const std::string& what) const {
  std::int64_t value = 0;
  std::string why;
  if (!parse_int64(token, value, why)) throw error(what + " " + quote(token) + " " + why);
  return value;
}

double TokenLines::real(std::string_view token, const std::string& what) const {
  double value = 0;
  std::string why;
  if (!parse_double(token, value, why)) throw error(what + " " + quote(token) + " " + why);
  return value;
}

std::size_t TokenLines::count(std::string_view token, const std::string& what) const {
  const std::int64_t value = integer(token, what);
  if (value < 0) throw error(what + " " + quote(token) + " is negative");
  if (value > std::int64_t(std::numeric_limits<std::uint32_t>::max()))
    throw error(what + " " + quote(token) + " is too large (more than 2^32 - 1)");
  return std::size_t(value);
}

void TokenLines::expect_tokens(std::size_t n, const std::string& what, const std::string& shape) const {
  if (tokens_.size() != n)
    throw error(what + " needs " + std::to_string(n) + " values (" + shape + "), got " + std::to_string(tokens_.size()));
}

}  // namespace fracref::coarse_detail
