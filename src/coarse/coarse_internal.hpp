#pragma once
// Helpers shared by the coarse builders. Not part of the public API.
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "coarse/coarse_model.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref::coarse_detail {

/// Union-find whose root is always the lowest index of its set.
class MinUnion {
 public:
  explicit MinUnion(std::size_t n) : parent_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
  }
  std::uint32_t find(std::uint32_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a < b) parent_[b] = a;
    else if (b < a) parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

/// Length of the diagonal of the points' bounding box (0 for no point).
double bbox_diagonal(const std::vector<glm::dvec3>& points);

/// Per point, the lowest index of its weld cluster: points whose coordinates all differ by at
/// most `tolerance` (absolute) are joined, transitively. tolerance 0 joins equal points only.
/// O(n log n) on a hashed grid of cell `tolerance`.
std::vector<std::uint32_t> weld_points(const std::vector<glm::dvec3>& points, double tolerance);

/// True when all three coordinates are finite.
inline bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// "'token'" for messages, shortened past 40 bytes, control bytes as \xNN.
std::string quote(std::string_view token);

/// "(x, y, z)" with up to 9 significant digits, for messages.
std::string point_text(const glm::dvec3& p);

/// A face of S before numbering: corners as welded model vertices (model.vertex_weld values),
/// wound so the normal points into `front`; the model vertex each side's piece uses at each corner.
struct SurfaceFace {
  glm::uvec3 welded;
  int front = 0, back = 0;
  glm::uvec3 front_model, back_model;
};

/// The InputError of assemble_surface() when S is invalid: a builder whose tets it made itself
/// (the cuts input) turns it into an internal error.
class InvalidSurfaceError : public InputError {
 public:
  using InputError::InputError;
};

/// Fills model.surface, surface_to_model_vertex and surface_copy_model_vertex from `faces`
/// (model.vertices, vertex_weld and piece_count must be set), then validates S.
/// \throw InvalidSurfaceError "<source>: the coarse fracture surface is invalid: ..." when
///        validate() fails.
void assemble_surface(CoarseModel& model, const std::vector<SurfaceFace>& faces, const std::string& source);

/// Sorted copy of a triangle's corners (a face's key independent of winding).
glm::uvec3 sorted_key(glm::uvec3 t);

/// True when (a, b, c) and (d, e, f) are the same cyclic order; false for the opposite order.
/// \pre both are permutations of the same three distinct ids.
bool same_winding(const glm::uvec3& x, const glm::uvec3& y);

/// Lexicographic order on uvec3.
inline bool key_less(const glm::uvec3& x, const glm::uvec3& y) {
  if (x.x != y.x) return x.x < y.x;
  if (x.y != y.y) return x.y < y.y;
  return x.z < y.z;
}

/// A face for the non-conformity check of pieces: a hull face (other = -1) of `piece`, or a face
/// of S between `piece` and `other`. `face` numbers it in its piece, for messages.
struct ConformFace {
  glm::uvec3 corners;
  int piece = 0;
  int other = -1;
  std::uint32_t face = 0;
};

/// The first pair (x, y) of faces of different pieces, x a hull face, such that y's corners lie
/// within plane_tolerance of x's plane and their interiors overlap there by more than
/// overlap_tolerance (separating-axis test in the plane); {-1, -1} when none. Sweep and prune
/// along the longest axis; deterministic.
std::pair<std::int64_t, std::int64_t> find_nonconforming(const std::vector<glm::dvec3>& positions,
                                                        const std::vector<ConformFace>& faces,
                                                        double plane_tolerance, double overlap_tolerance);

/// The data lines of a text file (blank lines and '#' comments skipped), split into tokens, with
/// located number parsing: every error names file:line.
class TokenLines {
 public:
  TokenLines(std::string file, std::string_view text) : file_(std::move(file)), cursor_(text) {}
  /// Advances to the next data line; false at the end of the text.
  bool next();
  const std::vector<std::string_view>& tokens() const { return tokens_; }
  std::size_t line() const { return cursor_.line_number(); }
  const std::string& file() const { return file_; }
  InputError error(const std::string& what) const { return input_error_at(file_, line(), what); }
  /// `what` names the value in messages, e.g. "vertex index".
  std::int64_t integer(std::string_view token, const std::string& what) const;
  double real(std::string_view token, const std::string& what) const;
  /// A count: an integer in [0, 2^32 - 1].
  std::size_t count(std::string_view token, const std::string& what) const;
  /// Throws unless the line has exactly n tokens; `shape` says what they are, e.g. "x y z ref".
  void expect_tokens(std::size_t n, const std::string& what, const std::string& shape) const;

 private:
  std::string file_;
  io_detail::LineCursor cursor_;
  std::vector<std::string_view> tokens_;
};

}  // namespace fracref::coarse_detail
