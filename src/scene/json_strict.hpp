#pragma once
// Strict JSON input: a parser that rejects duplicate keys and reports syntax errors by line and
// column, and ObjectReader, the validating reader every room uses for its part of a scene file.
//
// Message formats (all thrown as InputError):
//   "scene.json:7:12: syntax error while parsing value - invalid literal; last read: 'tru,'"
//   "scene.json:5:16: key 'refine.tau': number 1e999 is out of range"
//   "scene.json: key 'refine.tau': duplicate key"
//   "scene.json: key 'refine.tau': must be > 0, got -1"
// A key is named by its dotted path from the top of the file; array elements by "[i]"
// ("field.resolution[2]"). Lines and columns count from 1; a column counts bytes.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "util/error.hpp"

namespace fracref {

/// Parses `text` as one JSON value. `filename` only names the input in messages.
/// Stricter than nlohmann::json::parse: a key repeated in one object is an error (nlohmann
/// would silently keep the last one), and so is a number too large for a double (1e999).
/// \throw InputError "file:line:column: <cause>" for a syntax error or a number overflow,
///        "file: key 'a.b': duplicate key" for a repeated key.
nlohmann::json parse_json_strict(const std::string& text, const std::string& filename);

/// Reads and parses a whole file with parse_json_strict; messages name `path` as given.
/// \throw InputError when the file is missing, a folder, unreadable, larger than
///        max_input_file_bytes() (checked before reading), or its JSON is bad.
nlohmann::json read_json_file(const std::filesystem::path& path);

/// An interval of allowed real values; open or closed at each end. The default allows every
/// finite value.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;

  static Range at_least(double v) { return {v, std::numeric_limits<double>::infinity(), false, false}; }
  static Range greater_than(double v) { return {v, std::numeric_limits<double>::infinity(), true, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  /// [lo, hi)
  static Range half_open(double lo, double hi) { return {lo, hi, false, true}; }
  /// (lo, hi)
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }

  bool contains(double v) const;
  /// "must be > 0", "must be in [0, 60)", ... (empty when every value is allowed).
  std::string describe() const;
};

/// A closed interval of allowed integers.
struct IntRange {
  std::int64_t min = std::numeric_limits<std::int64_t>::min();
  std::int64_t max = std::numeric_limits<std::int64_t>::max();

  static IntRange at_least(std::int64_t v) { return {v, std::numeric_limits<std::int64_t>::max()}; }
  bool contains(std::int64_t v) const { return v >= min && v <= max; }
  std::string describe() const;
};

/// Reads the members of one JSON object with type and range checks, remembering which keys
/// were asked for, so that finish() can reject every key nobody asked for (a typo).
///
/// Types are strict: a number must be a JSON number (never a string such as "NaN", never
/// null), an integer must have no fractional part (5.0 and 1e3 are accepted as 5 and 1000,
/// 2.5 is not), a boolean must be true or false. Every getter throws InputError naming the
/// file and the key's dotted path. The reader keeps a pointer to the JSON value: the value
/// must outlive it.
class ObjectReader {
 public:
  /// `file` names the input in messages; `path` is the dotted path of `value` ("" for the top
  /// level, "refine", "field.params").
  /// \throw InputError when `value` is not an object.
  ObjectReader(const nlohmann::json& value, std::string file, std::string path);

  /// Whether `key` is present. Marks it as known (finish() will not reject it).
  bool has(const std::string& key);

  /// A finite number in `range`; `def` when the key is absent.
  double number(const std::string& key, double def, const Range& range = {});
  double number_required(const std::string& key, const Range& range = {});

  /// An integer in `range` (see the class comment for 5.0); `def` when absent.
  std::int64_t integer(const std::string& key, std::int64_t def, const IntRange& range = {});
  std::int64_t integer_required(const std::string& key, const IntRange& range = {});

  bool boolean(const std::string& key, bool def);
  bool boolean_required(const std::string& key);

  std::string string(const std::string& key, const std::string& def);
  std::string string_required(const std::string& key);

  /// A string that must be one of `allowed`; `def` when absent.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed, const std::string& def);
  std::string choice_required(const std::string& key, const std::vector<std::string>& allowed);

  /// An array of exactly three numbers, each in `range`.
  glm::dvec3 vec3(const std::string& key, const glm::dvec3& def, const Range& range = {});
  glm::dvec3 vec3_required(const std::string& key, const Range& range = {});
  /// An array of exactly three integers, each in `range`.
  /// \pre `range` lies within [0, 2^32 - 1].
  glm::uvec3 uvec3(const std::string& key, const glm::uvec3& def, const IntRange& range);
  glm::uvec3 uvec3_required(const std::string& key, const IntRange& range);
  /// An array of `count` numbers in `range` (any non-zero length when `count` is 0).
  std::vector<double> numbers_required(const std::string& key, std::size_t count, const Range& range = {});

  /// A non-empty path string; a relative one is resolved against `base_dir`. Returned
  /// absolute (if `base_dir` is) and lexically normal. Absent: an empty path. The file is
  /// not checked for existence.
  std::filesystem::path path(const std::string& key, const std::filesystem::path& base_dir);
  std::filesystem::path path_required(const std::string& key, const std::filesystem::path& base_dir);
  /// A non-empty array of path strings, resolved like path().
  std::vector<std::filesystem::path> paths_required(const std::string& key,
                                                     const std::filesystem::path& base_dir);

  /// A reader for the sub-object at `key` (path "<this path>.<key>"); nullopt when absent.
  std::optional<ObjectReader> object(const std::string& key);
  ObjectReader object_required(const std::string& key);
  /// The sub-object at `key` as JSON, unvalidated (to hand to another room's reader); an
  /// empty object when absent. \throw InputError when present but not an object.
  nlohmann::json raw_object(const std::string& key);

  /// Throws `error(key, reason)` when `key` is present: for keys that only some variants of
  /// an object allow ("'file' is only allowed when type is 'grid'"). Absent keys pass.
  void forbid(const std::string& key, const std::string& reason);

  /// \throw InputError naming the first key (in sorted order) that no getter or has() asked
  /// for, with a near-miss suggestion and the list of allowed keys.
  void finish() const;

  /// "file: key '<path>.<key>': what" — for checks that involve several keys.
  InputError error(const std::string& key, const std::string& what) const;
  /// "file: key '<path>': what" — an error about this object as a whole.
  InputError object_error(const std::string& what) const;
  /// The dotted path of `key` in this object.
  std::string key_path(const std::string& key) const;
  const std::string& file() const { return file_; }
  const std::string& object_path() const { return path_; }

 private:
  const nlohmann::json* find(const std::string& key);
  const nlohmann::json& get_required(const std::string& key);

  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
  std::vector<std::string> allowed_;  // asked-for keys, in the order asked
};

}  // namespace fracref
