// ObjectReader: typed, range-checked access to the members of one JSON object.
#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <utility>

#include "scene/json_strict.hpp"

namespace fracref {
namespace {

using nlohmann::json;

std::string format_number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

InputError key_error(const std::string& file, const std::string& path, const std::string& what) {
  if (path.empty()) return InputError(file + ": " + what);
  return InputError(file + ": key '" + path + "': " + what);
}

/// How a value reads in a message: numbers as written, strings quoted, long values cut.
std::string describe(const json& v) {
  std::string d = v.dump();
  if (d.size() > 60) d = d.substr(0, 57) + "...";
  if (v.is_string()) return "string " + d;
  if (v.is_boolean()) return "boolean " + d;
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return d;  // numbers and null
}

/// A hint for the common mistake of writing a number, NaN or infinity as a string.
std::string number_hint(const json& v) {
  if (!v.is_string()) return "";
  std::string s = v.get<std::string>();
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s = s.substr(1);
  if (s == "nan" || s == "inf" || s == "infinity") return " (JSON numbers cannot be NaN or infinite)";
  double d = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), d);
  if (res.ec == std::errc() && res.ptr == s.data() + s.size()) return " (write the number without quotes)";
  return "";
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

/// " (did you mean 'x'?)" for the closest candidate within two edits, else "". A '%' in
/// `question` stands for the candidate.
std::string suggestion(const std::string& given, const std::vector<std::string>& candidates,
                       const std::string& question = "did you mean '%'?") {
  std::string best;
  std::size_t best_d = 3;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(given, c);
    if (d < best_d && d < std::max(given.size(), c.size())) {
      best = c;
      best_d = d;
    }
  }
  if (best.empty()) return "";
  std::string q = question;
  return " (" + q.replace(q.find('%'), 1, best) + ")";
}

std::string quoted_list(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "'" : ", '") + i + "'";
  return s;
}

double as_number(const std::string& file, const std::string& path, const json& v, const Range& range) {
  if (!v.is_number()) throw key_error(file, path, "expected a number, got " + describe(v) + number_hint(v));
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw key_error(file, path, "must be a finite number, got " + format_number(d));
  if (!range.contains(d)) throw key_error(file, path, range.describe() + ", got " + describe(v));
  return d;
}

std::int64_t as_integer(const std::string& file, const std::string& path, const json& v, const IntRange& range) {
  if (!v.is_number()) throw key_error(file, path, "expected an integer, got " + describe(v) + number_hint(v));
  std::int64_t i = 0;
  if (v.is_number_unsigned()) {
    if (v.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max())) {
      throw key_error(file, path, "integer out of range, got " + describe(v));
    }
    i = std::int64_t(v.get<std::uint64_t>());
  } else if (v.is_number_integer()) {
    i = v.get<std::int64_t>();
  } else {
    const double d = v.get<double>();
    if (!std::isfinite(d) || d != std::trunc(d)) throw key_error(file, path, "expected an integer, got " + describe(v));
    if (d < -9.2233720368547758e18 || d >= 9.2233720368547758e18) {
      throw key_error(file, path, "integer out of range, got " + describe(v));
    }
    i = std::int64_t(d);
  }
  if (!range.contains(i)) throw key_error(file, path, range.describe() + ", got " + describe(v));
  return i;
}

std::string as_string(const std::string& file, const std::string& path, const json& v) {
  if (!v.is_string()) throw key_error(file, path, "expected a string, got " + describe(v));
  return v.get<std::string>();
}

std::filesystem::path as_path(const std::string& file, const std::string& path, const json& v,
                              const std::filesystem::path& base_dir) {
  const std::string s = as_string(file, path, v);
  if (s.empty()) throw key_error(file, path, "the path must not be empty");
  if (s.find('\0') != std::string::npos) throw key_error(file, path, "the path must not contain a NUL character");
  const std::filesystem::path p(s);
  return (p.is_absolute() ? p : base_dir / p).lexically_normal();
}

/// The elements of an array value (with their paths), checked for the expected length.
const json& as_array(const std::string& file, const std::string& path, const json& v, std::size_t count) {
  if (!v.is_array()) throw key_error(file, path, "expected an array, got " + describe(v));
  if (count != 0 && v.size() != count) {
    throw key_error(file, path, "expected an array of " + std::to_string(count) + " elements, got " +
                                    std::to_string(v.size()));
  }
  if (count == 0 && v.empty()) throw key_error(file, path, "the array must not be empty");
  return v;
}

std::string index_path(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

}  // namespace

bool Range::contains(double v) const {
  const bool lo = min_open ? v > min : v >= min;
  const bool hi = max_open ? v < max : v <= max;
  return lo && hi;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return "must be in " + std::string(min_open ? "(" : "[") + format_number(min) + ", " + format_number(max) +
           (max_open ? ")" : "]");
  }
  if (has_min) return std::string("must be ") + (min_open ? "> " : ">= ") + format_number(min);
  if (has_max) return std::string("must be ") + (max_open ? "< " : "<= ") + format_number(max);
  return "";
}

std::string IntRange::describe() const {
  constexpr auto lowest = std::numeric_limits<std::int64_t>::min();
  constexpr auto highest = std::numeric_limits<std::int64_t>::max();
  if (min != lowest && max != highest) {
    return "must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  }
  if (min != lowest) return "must be an integer >= " + std::to_string(min);
  if (max != highest) return "must be an integer <= " + std::to_string(max);
  return "";
}

ObjectReader::ObjectReader(const nlohmann::json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {
  if (!value.is_object()) {
    throw key_error(file_, path_, (path_.empty() ? "the top level must be a JSON object, got "
                                                 : "expected an object, got ") + describe(value));
  }
}

std::string ObjectReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

InputError ObjectReader::error(const std::string& key, const std::string& what) const {
  return key_error(file_, key_path(key), what);
}

InputError ObjectReader::object_error(const std::string& what) const { return key_error(file_, path_, what); }

const nlohmann::json* ObjectReader::find(const std::string& key) {
  if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end()) allowed_.push_back(key);
  const auto it = value_->find(key);
  return it == value_->end() ? nullptr : &*it;
}

const nlohmann::json& ObjectReader::get_required(const std::string& key) {
  const json* v = find(key);
  if (v == nullptr) {
    std::vector<std::string> unread;  // a present key that nobody asked for may be a typo of this one
    for (const auto& item : value_->items()) {
      if (std::find(allowed_.begin(), allowed_.end(), item.key()) == allowed_.end()) unread.push_back(item.key());
    }
    throw error(key, "required key is missing" + suggestion(key, unread, "is '%' a misspelling of it?"));
  }
  return *v;
}

bool ObjectReader::has(const std::string& key) { return find(key) != nullptr; }

double ObjectReader::number(const std::string& key, double def, const Range& range) {
  const json* v = find(key);
  return v ? as_number(file_, key_path(key), *v, range) : def;
}

double ObjectReader::number_required(const std::string& key, const Range& range) {
  return as_number(file_, key_path(key), get_required(key), range);
}

std::int64_t ObjectReader::integer(const std::string& key, std::int64_t def, const IntRange& range) {
  const json* v = find(key);
  return v ? as_integer(file_, key_path(key), *v, range) : def;
}

std::int64_t ObjectReader::integer_required(const std::string& key, const IntRange& range) {
  return as_integer(file_, key_path(key), get_required(key), range);
}

bool ObjectReader::boolean(const std::string& key, bool def) {
  return has(key) ? boolean_required(key) : def;
}

bool ObjectReader::boolean_required(const std::string& key) {
  const json& v = get_required(key);
  if (!v.is_boolean()) throw error(key, "expected true or false, got " + describe(v));
  return v.get<bool>();
}

std::string ObjectReader::string(const std::string& key, const std::string& def) {
  return has(key) ? string_required(key) : def;
}

std::string ObjectReader::string_required(const std::string& key) {
  return as_string(file_, key_path(key), get_required(key));
}

std::string ObjectReader::choice(const std::string& key, const std::vector<std::string>& allowed,
                                 const std::string& def) {
  return has(key) ? choice_required(key, allowed) : def;
}

std::string ObjectReader::choice_required(const std::string& key, const std::vector<std::string>& allowed) {
  const std::string s = string_required(key);
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    throw error(key, "must be one of " + quoted_list(allowed) + ", got '" + s + "'" + suggestion(s, allowed));
  }
  return s;
}

glm::dvec3 ObjectReader::vec3(const std::string& key, const glm::dvec3& def, const Range& range) {
  return has(key) ? vec3_required(key, range) : def;
}

glm::dvec3 ObjectReader::vec3_required(const std::string& key, const Range& range) {
  const std::vector<double> v = numbers_required(key, 3, range);
  return {v[0], v[1], v[2]};
}

glm::uvec3 ObjectReader::uvec3(const std::string& key, const glm::uvec3& def, const IntRange& range) {
  return has(key) ? uvec3_required(key, range) : def;
}

glm::uvec3 ObjectReader::uvec3_required(const std::string& key, const IntRange& range) {
  const std::string p = key_path(key);
  const json& a = as_array(file_, p, get_required(key), 3);
  glm::uvec3 out;
  for (int i = 0; i < 3; ++i) out[i] = unsigned(as_integer(file_, index_path(p, i), a[i], range));
  return out;
}

std::vector<double> ObjectReader::numbers_required(const std::string& key, std::size_t count, const Range& range) {
  const std::string p = key_path(key);
  const json& a = as_array(file_, p, get_required(key), count);
  std::vector<double> out;
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(as_number(file_, index_path(p, i), a[i], range));
  return out;
}

std::filesystem::path ObjectReader::path(const std::string& key, const std::filesystem::path& base_dir) {
  return has(key) ? path_required(key, base_dir) : std::filesystem::path();
}

std::filesystem::path ObjectReader::path_required(const std::string& key, const std::filesystem::path& base_dir) {
  return as_path(file_, key_path(key), get_required(key), base_dir);
}

std::vector<std::filesystem::path> ObjectReader::paths_required(const std::string& key,
                                                                const std::filesystem::path& base_dir) {
  const std::string p = key_path(key);
  const json& a = as_array(file_, p, get_required(key), 0);
  std::vector<std::filesystem::path> out;
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(as_path(file_, index_path(p, i), a[i], base_dir));
  return out;
}

std::optional<ObjectReader> ObjectReader::object(const std::string& key) {
  const json* v = find(key);
  if (v == nullptr) return std::nullopt;
  return ObjectReader(*v, file_, key_path(key));
}

ObjectReader ObjectReader::object_required(const std::string& key) {
  return ObjectReader(get_required(key), file_, key_path(key));
}

nlohmann::json ObjectReader::raw_object(const std::string& key) {
  const json* v = find(key);
  if (v == nullptr) return json::object();
  if (!v->is_object()) throw error(key, "expected an object, got " + describe(*v));
  return *v;
}

void ObjectReader::forbid(const std::string& key, const std::string& reason) {
  if (value_->contains(key)) throw error(key, reason);
}

void ObjectReader::finish() const {
  for (const auto& item : value_->items()) {
    if (std::find(allowed_.begin(), allowed_.end(), item.key()) != allowed_.end()) continue;
    std::string what = "unknown key" + suggestion(item.key(), allowed_);
    what += allowed_.empty() ? "; this object takes no keys" : "; allowed keys: " + quoted_list(allowed_);
    throw error(item.key(), what);
  }
}

}  // namespace fracref
