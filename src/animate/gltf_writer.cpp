// animation.glb: the pieces and their animation as glTF 2.0 morph targets (see gltf_writer.hpp).
#include "animate/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <string_view>

#include "animate/animate_internal.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using animate_detail::LocalFaces;
using animate_detail::Tri;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

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

std::string numbered(const char* format, std::size_t n) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, n);
  return buffer;
}

void put_u32(std::string& bin, std::uint32_t v) {
  const char bytes[4] = {char(v & 0xFF), char((v >> 8) & 0xFF), char((v >> 16) & 0xFF), char((v >> 24) & 0xFF)};
  bin.append(bytes, 4);
}

void put_f32(std::string& bin, float v) { put_u32(bin, std::bit_cast<std::uint32_t>(v)); }

struct View {
  std::size_t offset = 0, length = 0;
  int target = 0;  // 0: none (animation data)
};

struct Accessor {
  int view = -1;  // -1: no buffer view, all zeros
  int component = kFloat;
  std::size_t count = 0;
  const char* type = "SCALAR";
  std::vector<float> min, max;  // empty: not written
};

// The binary chunk and what describes it, built in file order.
struct Glb {
  std::string bin;
  std::vector<View> views;
  std::vector<Accessor> accessors;

  std::size_t add(Accessor a, std::size_t begin, int target) {
    if (begin != std::string::npos) {
      views.push_back({begin, bin.size() - begin, target});
      a.view = int(views.size() - 1);
    }
    accessors.push_back(std::move(a));
    return accessors.size() - 1;
  }
};

// Appends float VEC3 data with its bounds; all-zero data becomes an accessor without a view.
std::size_t add_vec3(Glb& g, const std::vector<float>& xyz) {
  Accessor a;
  a.count = xyz.size() / 3;
  a.type = "VEC3";
  a.min.assign(3, std::numeric_limits<float>::infinity());
  a.max.assign(3, -std::numeric_limits<float>::infinity());
  bool zero = true;
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    a.min[i % 3] = std::min(a.min[i % 3], xyz[i]);
    a.max[i % 3] = std::max(a.max[i % 3], xyz[i]);
    zero = zero && xyz[i] == 0.0f;
  }
  if (zero) {
    a.min.assign(3, 0.0f), a.max.assign(3, 0.0f);
    return g.add(std::move(a), std::string::npos, 0);
  }
  const std::size_t begin = g.bin.size();
  for (float v : xyz) put_f32(g.bin, v);
  return g.add(std::move(a), begin, kArrayBuffer);
}

std::size_t add_indices(Glb& g, const std::vector<Tri>& faces, const std::vector<std::uint8_t>& inside, std::uint8_t group) {
  Accessor a;
  a.component = kUnsignedInt;
  const std::size_t begin = g.bin.size();
  for (std::size_t t = 0; t < faces.size(); ++t)
    if (inside[t] == group)
      for (std::uint32_t v : faces[t]) put_u32(g.bin, v), ++a.count;
  return g.add(std::move(a), begin, kElementArrayBuffer);
}

std::size_t add_scalars(Glb& g, const std::vector<float>& values, bool bounds) {
  Accessor a;
  a.count = values.size();
  if (bounds) a.min = {values.front()}, a.max = {values.back()};  // ascending times
  const std::size_t begin = g.bin.size();
  for (float v : values) put_f32(g.bin, v);
  return g.add(std::move(a), begin, 0);
}

struct FrameSource {
  const PieceLayout& layout;
  std::size_t count = 0;
  double fps = 24.0;
  std::function<std::vector<glm::dvec3>(std::size_t)> frame;
};

std::vector<glm::dvec3> frame_positions(const FrameSource& src, std::size_t f) {
  std::vector<glm::dvec3> x = src.frame(f);
  if (x.size() != src.layout.slot_count())
    throw RunError("animation.glb: frame " + std::to_string(f) + " has " + std::to_string(x.size()) +
                   " positions, expected " + std::to_string(src.layout.slot_count()));
  for (std::size_t s = 0; s < x.size(); ++s)
    if (!std::isfinite(x[s].x) || !std::isfinite(x[s].y) || !std::isfinite(x[s].z))
      throw RunError("animation.glb: frame " + std::to_string(f) + ": position " + std::to_string(s) + " is not finite");
  return x;
}

// Per piece, the accessors of its mesh.
struct MeshRefs {
  std::size_t position = 0;
  std::optional<std::size_t> exterior, inside;
  std::vector<std::size_t> targets;  // one POSITION accessor per kept frame after the first
};

// Frame 0 as the base positions (kept in float: the deltas are taken from what readers see).
std::vector<MeshRefs> add_base(Glb& g, const LocalFaces& faces, const PieceLayout& layout,
                               const std::vector<glm::dvec3>& x, std::vector<float>& base) {
  std::vector<MeshRefs> meshes(faces.faces.size());
  for (const glm::dvec3& p : x) base.insert(base.end(), {float(p.x), float(p.y), float(p.z)});
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    if (layout.offsets[p] == layout.offsets[p + 1] || faces.faces[p].empty())
      throw RunError("animation.glb: piece " + std::to_string(p) + " has no triangle");
    meshes[p].position = add_vec3(g, std::vector<float>(base.begin() + 3 * layout.offsets[p], base.begin() + 3 * layout.offsets[p + 1]));
    const auto& inside = faces.inside[p];
    if (std::count(inside.begin(), inside.end(), 0)) meshes[p].exterior = add_indices(g, faces.faces[p], inside, 0);
    if (std::count(inside.begin(), inside.end(), 1)) meshes[p].inside = add_indices(g, faces.faces[p], inside, 1);
  }
  return meshes;
}

void add_targets(Glb& g, std::vector<MeshRefs>& meshes, const PieceLayout& layout, const std::vector<float>& base,
                 const std::vector<glm::dvec3>& x) {
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    std::vector<float> delta;
    delta.reserve(3 * (layout.offsets[p + 1] - layout.offsets[p]));
    for (std::uint32_t s = layout.offsets[p]; s < layout.offsets[p + 1]; ++s)
      for (int k = 0; k < 3; ++k) delta.push_back(float(x[s][k] - double(base[3 * s + k])));
    meshes[p].targets.push_back(add_vec3(g, delta));
  }
}

// Frame times, and per time the weights of every target: the unit vector of the frame's target.
std::pair<std::size_t, std::size_t> add_keys(Glb& g, const std::vector<std::size_t>& kept, double fps) {
  std::vector<float> times, weights;
  for (std::size_t j = 0; j < kept.size(); ++j) {
    times.push_back(float(double(kept[j]) / fps));
    for (std::size_t t = 1; t < kept.size(); ++t) weights.push_back(t == j ? 1.0f : 0.0f);
  }
  const std::size_t input = add_scalars(g, times, true);
  return {input, add_scalars(g, weights, false)};
}

// The file's size, but for the fixed part of the JSON (an accessor, view and target reference
// take under 256 bytes of JSON per piece and kept frame).
std::size_t data_bytes(std::size_t kept, std::size_t vertices, std::size_t indices, std::size_t pieces) {
  return 12 * vertices * kept + 4 * indices + 4 * kept + 4 * kept * (kept - 1) + 256 * pieces * kept;
}

// gltf_kept_frames(frames, step).size(), without building the list.
std::size_t kept_count(std::size_t frames, std::size_t step) {
  return frames == 0 ? 0 : (frames - 1) / step + 1 + ((frames - 1) % step ? 1 : 0);
}

GltfSummary plan(const FrameSource& src, const LocalFaces& faces, const GltfOptions& o) {
  std::size_t indices = 0;
  for (const auto& f : faces.faces) indices += 3 * f.size();
  GltfSummary s;
  s.frame_count = src.count;
  for (s.frame_step = 1;; ++s.frame_step) {
    s.frames_kept = kept_count(src.count, s.frame_step);
    const std::size_t bytes = data_bytes(s.frames_kept, src.layout.slot_count(), indices, faces.faces.size());
    if (bytes <= o.max_bytes) break;
    if (s.frames_kept <= 2) {
      s.over_budget = true;
      break;
    }
  }
  return s;
}

void write_asset(JsonWriter& w) {
  w.key("asset").open('{').key("version").str("2.0").key("generator").str("fracref").close('}');
  w.key("scene").integer(0);
}

void write_nodes(JsonWriter& w, std::size_t count) {
  w.key("scenes").open('[').open('{').key("name").str("fracture").key("nodes").open('[');
  for (std::size_t p = 0; p < count; ++p) w.integer(p);
  w.close(']').close('}').close(']');
  w.key("nodes").open('[');
  for (std::size_t p = 0; p < count; ++p) w.open('{').key("name").str(numbered("piece_%03zu", p)).key("mesh").integer(p).close('}');
  w.close(']');
}

void write_primitive(JsonWriter& w, const MeshRefs& m, std::size_t indices, int material) {
  w.open('{').key("attributes").open('{').key("POSITION").integer(m.position).close('}');
  w.key("indices").integer(indices).key("material").integer(std::uint64_t(material)).key("mode").integer(4);
  if (!m.targets.empty()) {
    w.key("targets").open('[');
    for (std::size_t t : m.targets) w.open('{').key("POSITION").integer(t).close('}');
    w.close(']');
  }
  w.close('}');
}

void write_meshes(JsonWriter& w, const std::vector<MeshRefs>& meshes, const std::vector<std::size_t>& kept) {
  w.key("meshes").open('[');
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    w.open('{').key("name").str(numbered("piece_%03zu", p)).key("primitives").open('[');
    if (meshes[p].exterior) write_primitive(w, meshes[p], *meshes[p].exterior, 0);
    if (meshes[p].inside) write_primitive(w, meshes[p], *meshes[p].inside, 1);
    w.close(']');
    if (kept.size() > 1) {
      w.key("extras").open('{').key("targetNames").open('[');
      for (std::size_t j = 1; j < kept.size(); ++j) w.str(numbered("frame_%04zu", kept[j]));
      w.close(']').close('}');
    }
    w.close('}');
  }
  w.close(']');
}

// The colours of frames.mtl (outside grey, inside warm), as linear base colours.
void write_materials(JsonWriter& w) {
  w.key("materials").open('[');
  const std::pair<const char*, std::array<double, 3>> materials[] = {{"exterior", {0.8, 0.8, 0.8}}, {"inside", {0.85, 0.55, 0.35}}};
  for (const auto& [name, rgb] : materials) {
    w.open('{').key("name").str(name).key("pbrMetallicRoughness").open('{').key("baseColorFactor").open('[');
    for (double c : rgb) w.real(c);
    w.real(1.0).close(']').key("metallicFactor").real(0.0).key("roughnessFactor").real(0.8).close('}');
    w.key("doubleSided").boolean(false).close('}');
  }
  w.close(']');
}

void write_bounds(JsonWriter& w, const char* key, const std::vector<float>& values) {
  w.key(key).open('[');
  for (float v : values) w.real(double(v));
  w.close(']');
}

void write_accessors(JsonWriter& w, const Glb& g) {
  w.key("accessors").open('[');
  for (const Accessor& a : g.accessors) {
    w.open('{');
    if (a.view >= 0) w.key("bufferView").integer(std::uint64_t(a.view));
    w.key("componentType").integer(std::uint64_t(a.component)).key("count").integer(a.count).key("type").str(a.type);
    if (!a.min.empty()) write_bounds(w, "min", a.min), write_bounds(w, "max", a.max);
    w.close('}');
  }
  w.close(']');
  w.key("bufferViews").open('[');
  for (const View& v : g.views) {
    w.open('{').key("buffer").integer(0).key("byteOffset").integer(v.offset).key("byteLength").integer(v.length);
    if (v.target) w.key("target").integer(std::uint64_t(v.target));
    w.close('}');
  }
  w.close(']');
  w.key("buffers").open('[').open('{').key("byteLength").integer(g.bin.size()).close('}').close(']');
}

void write_animation(JsonWriter& w, std::size_t nodes, std::pair<std::size_t, std::size_t> keys, const GltfSummary& s) {
  w.key("animations").open('[').open('{').key("name").str("fracture").key("channels").open('[');
  for (std::size_t p = 0; p < nodes; ++p)
    w.open('{').key("sampler").integer(p).key("target").open('{').key("node").integer(p).key("path").str("weights").close('}').close('}');
  w.close(']').key("samplers").open('[');
  for (std::size_t p = 0; p < nodes; ++p)
    w.open('{').key("input").integer(keys.first).key("interpolation").str("LINEAR").key("output").integer(keys.second).close('}');
  w.close(']').key("extras").open('{').key("frame_count").integer(s.frame_count).key("frame_step").integer(s.frame_step);
  w.close('}').close('}').close(']');
}

void put_chunk(std::string& out, std::uint32_t type, const std::string& data, char pad) {
  const std::size_t padded = (data.size() + 3) / 4 * 4;
  put_u32(out, std::uint32_t(padded));
  put_u32(out, type);
  out += data;
  out.append(padded - data.size(), pad);
}

std::string assemble(const std::string& json, const std::string& bin) {
  const std::size_t total = 12 + 8 + (json.size() + 3) / 4 * 4 + 8 + (bin.size() + 3) / 4 * 4;
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw RunError("animation.glb: " + std::to_string(total) + " bytes, over the 4 GiB a GLB file can hold");
  std::string out;
  out.reserve(total);
  put_u32(out, kGlbMagic);
  put_u32(out, 2);
  put_u32(out, std::uint32_t(total));
  put_chunk(out, kChunkJson, json, ' ');
  put_chunk(out, kChunkBin, bin, '\0');
  return out;
}

std::string encode(const PieceSet& pieces, const FrameSource& src, const GltfOptions& o, GltfSummary* summary) {
  if (src.count == 0) throw RunError("animation.glb: the animation has no frame");
  if (!(src.fps > 0.0) || !std::isfinite(src.fps)) throw RunError("animation.glb: fps " + std::to_string(src.fps) + " is not > 0");
  const LocalFaces faces = animate_detail::local_faces(pieces, src.layout, "animation.glb");
  GltfSummary s = plan(src, faces, o);
  const std::vector<std::size_t> kept = gltf_kept_frames(src.count, s.frame_step);
  Glb g;
  std::vector<float> base;
  std::vector<MeshRefs> meshes = add_base(g, faces, src.layout, frame_positions(src, 0), base);
  for (std::size_t j = 1; j < kept.size(); ++j) add_targets(g, meshes, src.layout, base, frame_positions(src, kept[j]));
  std::pair<std::size_t, std::size_t> keys;
  if (kept.size() > 1) keys = add_keys(g, kept, src.fps);
  JsonWriter w;
  w.open('{');
  write_asset(w);
  write_nodes(w, meshes.size());
  write_meshes(w, meshes, kept);
  write_materials(w);
  write_accessors(w, g);
  if (kept.size() > 1) write_animation(w, meshes.size(), keys, s);
  w.close('}');
  std::string out = assemble(w.text(), g.bin);
  s.bytes = out.size();
  if (summary) *summary = s;
  return out;
}

}  // namespace

std::vector<std::size_t> gltf_kept_frames(std::size_t frame_count, std::size_t step) {
  std::vector<std::size_t> kept;
  step = std::max<std::size_t>(step, 1);
  for (std::size_t f = 0; f < frame_count; f += step) kept.push_back(f);
  if (frame_count > 0 && kept.back() != frame_count - 1) kept.push_back(frame_count - 1);
  return kept;
}

std::string encode_animation_glb(const PieceSet& pieces, const AnimationResult& result, const GltfOptions& options,
                                 GltfSummary* summary) {
  const FrameSource src{result.layout, result.frames.size(), result.fps, [&](std::size_t f) { return result.frames[f]; }};
  return encode(pieces, src, options, summary);
}

GltfSummary write_animation_glb(const PieceSet& pieces, const AnimationResult& result, const std::filesystem::path& file,
                                const GltfOptions& options) {
  GltfSummary s;
  write_file_atomic(file, encode_animation_glb(pieces, result, options, &s));
  return s;
}

GltfSummary write_animation_glb(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                                const std::filesystem::path& file, const GltfOptions& options) {
  const FrameSource src{transfer.layout, transfer.frame_count, animation.fps,
                        [&](std::size_t f) { return transfer_frame(transfer, animation, f); }};
  GltfSummary s;
  write_file_atomic(file, encode(pieces, src, options, &s));
  return s;
}

}  // namespace fracref
