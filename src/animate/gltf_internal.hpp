#pragma once
// Internal to animation.glb's writer: the JSON writer, the binary chunk under construction, and
// the motion analysis that decides which pieces move rigidly.
#include <charconv>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "animate/animate.hpp"

namespace fracref::gltf_detail {

// Compact JSON in the order it is written; commas are placed by the writer, not the caller.
class JsonWriter {
 public:
  JsonWriter& open(char bracket) {
    separate();
    text_ += bracket;
    comma_ = false;
    return *this;
  }
  JsonWriter& close(char bracket) {
    text_ += bracket;
    comma_ = true;
    return *this;
  }
  JsonWriter& key(std::string_view name) {
    separate();
    quoted(name);
    text_ += ':';
    comma_ = false;
    return *this;
  }
  JsonWriter& str(std::string_view value) {
    separate();
    quoted(value);
    comma_ = true;
    return *this;
  }
  JsonWriter& boolean(bool value) {
    separate();
    text_ += value ? "true" : "false";
    comma_ = true;
    return *this;
  }
  JsonWriter& integer(std::uint64_t value) {
    separate();
    text_ += std::to_string(value);
    comma_ = true;
    return *this;
  }
  // Shortest text that reads back to the same double: a float widened to double is written
  // exactly, so accessor bounds match the data whether a reader compares in float or double.
  JsonWriter& real(double value) {
    char buffer[40];
    separate();
    text_.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
    comma_ = true;
    return *this;
  }
  std::string& text() { return text_; }

 private:
  void separate() {
    if (comma_) text_ += ',';
  }
  void quoted(std::string_view s) {
    text_ += '"';
    for (char c : s) {
      if (c == '"' || c == '\\') text_ += '\\';
      text_ += c;
    }
    text_ += '"';
  }
  std::string text_;
  bool comma_ = false;
};

inline constexpr int kFloat = 5126, kUnsignedInt = 5125;
inline constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

struct View {
  std::size_t offset = 0, length = 0;
  int target = 0;  // 0: none (animation and sparse data)
};

struct Accessor {
  int view = -1;  // -1: no buffer view, zeros (and the sparse values, if any)
  int component = kFloat;
  std::size_t count = 0;
  const char* type = "SCALAR";
  std::vector<float> min, max;  // empty: not written
  std::size_t sparse_count = 0;
  int sparse_indices = -1, sparse_values = -1;  // buffer views
};

/// The binary chunk and what describes it, built in file order.
struct Glb {
  std::string bin;
  std::vector<View> views;
  std::vector<Accessor> accessors;

  /// A view of bin[begin, end of bin) (none when begin is npos) and `a` on it; returns its index.
  std::size_t add(Accessor a, std::size_t begin, int target);
  /// A view of bin[begin, end of bin); returns its index.
  int add_view(std::size_t begin, int target);
};

void put_u32(std::string& bin, std::uint32_t v);
void put_f32(std::string& bin, float v);

/// Float data of `width` components per element (type "VEC2", "VEC3", "VEC4" or "SCALAR"), with
/// min/max when `bounds`. \pre values.size() is a multiple of width.
std::size_t add_floats(Glb& g, const std::vector<float>& values, int width, const char* type, bool bounds, int target);

/// A morph target's POSITION deltas (VEC3, with min/max): no data when all zero, sparse (uint32
/// indices of the vertices that move, and their values) when that is smaller, dense otherwise.
std::size_t add_target(Glb& g, const std::vector<float>& xyz);

/// Where the frames come from, one at a time.
struct FrameSource {
  const PieceLayout& layout;
  std::size_t count = 0;
  double fps = 24.0;
  std::function<std::vector<glm::dvec3>(std::size_t)> frame;
};

/// Frame f, checked: one finite position per slot. 	hrow RunError naming animation.glb.
std::vector<glm::dvec3> frame_positions(const FrameSource& src, std::size_t f);

/// How one piece moves in animation.glb.
struct PieceMotion {
  bool rigid = false;
  glm::dvec3 pivot{0.0};                 ///< the rest vertices' centroid: the mesh's origin
  std::vector<glm::vec3> translation;    ///< per frame (rigid only)
  std::vector<glm::vec4> rotation;       ///< per frame, glTF order x, y, z, w (rigid only)
};

/// Per piece: rigid when, in every frame, the pose fit_rigid finds, written in float32 (the
/// rotation as a quaternion, the translation, the rest vertices less the pivot), puts every
/// vertex within `tolerance` of its position. `rest` is per piece its material-space vertices.
/// 	hrow RunError as frame_positions.
std::vector<PieceMotion> analyse_motion(const FrameSource& src, const std::vector<std::vector<glm::dvec3>>& rest,
                                        double tolerance);

}  // namespace fracref::gltf_detail
