#pragma once
// Internal to the glb check: animation.glb as read back (its own reader, not the writer's code).
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "check/check_internal.hpp"

namespace fracref::check_detail {

/// The first thing wrong with the file; caught once, recorded as the check's failure.
struct Problem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct AccessorInfo {
  int component = 0;
  std::string type;
  std::size_t count = 0;
  bool has_view = false, has_bounds = false;
  std::size_t offset = 0;  ///< in the BIN chunk
  std::size_t sparse_count = 0, sparse_indices = 0, sparse_values = 0;  ///< offsets in the BIN chunk
  int sparse_component = 0;
};

/// The parsed file: JSON, BIN chunk, and every accessor checked to lie inside it.
struct GlbFile {
  nlohmann::json j;
  std::string bin;
  std::vector<AccessorInfo> acc;
};

std::uint32_t u32_at(const std::string& bytes, std::size_t offset);
/// j[key] as an array (empty when absent). \throw Problem when it is not an array.
const nlohmann::json& array_of(const nlohmann::json& j, const char* key, const std::string& where);
/// j[key], an integer below limit. \throw Problem otherwise.
std::size_t index_at(const nlohmann::json& j, const char* key, const std::string& where, std::size_t limit);
std::size_t optional_size(const nlohmann::json& j, const char* key, const std::string& where);
std::string name_at(const char* what, std::size_t i);

/// The values of float accessor `index` (`width` components per element), zeros where it has no
/// view, sparse values applied. \throw Problem when it is not float of that width, or a sparse
/// index is out of range or not increasing.
std::vector<double> float_values(const GlbFile& g, std::size_t index, std::size_t width, const std::string& where);

/// Per piece, what the glb check found: all its checks and the count of its morph targets.
struct GlbSummary {
  std::size_t rigid = 0, deforming = 0, targets = 0;
};

/// Nodes, meshes, primitives and the animation against the piece files (gltf_writer.hpp's
/// layout). \throw Problem naming the first thing wrong.
GlbSummary check_glb_pieces(const GlbFile& g, const std::vector<PieceFile>& pieces, std::size_t frames);

/// Piece p's first n mesh vertices (n: its piece file's) where the glb puts them at animation
/// key `key`: node translation, rotation and scale (animated or static) applied to POSITION
/// plus the weighted morph targets. \pre check_glb_pieces passed.
std::vector<glm::dvec3> glb_positions(const GlbFile& g, std::size_t p, std::size_t n, std::size_t key);

/// The glb_frames check: at every kept frame, every piece vertex where the glb puts it within
/// 1e-6 of the piece files' bounding-box diagonal of `frame`'s. \throw Problem or InputError.
void check_glb_frames(const GlbFile& g, const std::vector<PieceFile>& pieces, std::size_t frames, const FrameReader& frame,
                      CheckReport& report);

/// The frames animation.glb keeps (0, step, 2 step, ... and the last) per animations[0].extras.
std::vector<std::size_t> glb_kept_frames(const GlbFile& g, std::size_t frames);

}  // namespace fracref::check_detail
