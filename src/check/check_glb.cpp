// The glb check: animation.glb read back with its own GLB reader (not the writer's code) and held
// against glTF 2.0 and against the piece files and report.json.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "scene/json_strict.hpp"

#include "check/check_internal.hpp"

namespace fracref::check_detail {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Tri = std::array<std::uint32_t, 3>;

// The first thing wrong with the file; caught once, recorded as the check's failure.
struct Problem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

constexpr std::uint32_t kMagic = 0x46546C67, kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;

std::uint32_t u32_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | std::uint8_t(bytes[offset + std::size_t(k)]);
  return v;
}

std::string hex(std::uint32_t v) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "0x%08X", v);
  return buffer;
}

struct GlbParts {
  std::string json, bin;
};

// The 12-byte header and the JSON and BIN chunks (glTF 2.0, "GLB File Format Specification").
GlbParts split_glb(const std::string& bytes) {
  if (bytes.size() < 20) throw Problem(std::to_string(bytes.size()) + " bytes, shorter than a GLB header and chunk header");
  if (u32_at(bytes, 0) != kMagic) throw Problem("magic " + hex(u32_at(bytes, 0)) + ", expected 0x46546C67 ('glTF')");
  if (u32_at(bytes, 4) != 2) throw Problem("container version " + std::to_string(u32_at(bytes, 4)) + ", expected 2");
  if (u32_at(bytes, 8) != bytes.size())
    throw Problem("header length " + std::to_string(u32_at(bytes, 8)) + ", the file has " + std::to_string(bytes.size()) + " bytes");
  GlbParts parts;
  std::size_t at = 12;
  for (int chunk = 0; chunk < 2 && at < bytes.size(); ++chunk) {
    if (bytes.size() - at < 8) throw Problem("chunk " + std::to_string(chunk) + " header cut off at byte " + std::to_string(at));
    const std::uint32_t length = u32_at(bytes, at), type = u32_at(bytes, at + 4), want = chunk ? kChunkBin : kChunkJson;
    if (type != want) throw Problem("chunk " + std::to_string(chunk) + " has type " + hex(type) + ", expected " + hex(want));
    if (length % 4) throw Problem("chunk " + std::to_string(chunk) + " length " + std::to_string(length) + " is not a multiple of 4");
    if (length > bytes.size() - at - 8)
      throw Problem("chunk " + std::to_string(chunk) + " length " + std::to_string(length) + " runs past the end of the file");
    (chunk ? parts.bin : parts.json) = bytes.substr(at + 8, length);
    at += 8 + length;
  }
  if (at != bytes.size()) throw Problem(std::to_string(bytes.size() - at) + " bytes after the BIN chunk");
  return parts;
}

// The project's strict JSON reader (a repeated key, which nlohmann alone would silently merge,
// is an error too).
Json parse_json(const std::string& text) {
  Json j;
  try {
    j = parse_json_strict(text, "JSON chunk");
  } catch (const InputError& e) {
    throw Problem(e.what());
  }
  if (!j.is_object()) throw Problem("JSON chunk: not a JSON object");
  return j;
}

// j[key] as an array (empty when absent).
const Json& array_of(const Json& j, const char* key, const std::string& where) {
  static const Json empty = Json::array();
  if (!j.contains(key)) return empty;
  if (!j[key].is_array()) throw Problem(where + "." + key + " is not an array");
  return j[key];
}

std::size_t index_at(const Json& j, const char* key, const std::string& where, std::size_t limit) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number_unsigned())
    throw Problem(where + "." + key + " missing or not a non-negative integer");
  const std::size_t v = j[key].get<std::size_t>();
  if (v >= limit) throw Problem(where + "." + key + " = " + std::to_string(v) + ", out of range (" + std::to_string(limit) + ")");
  return v;
}

std::size_t optional_size(const Json& j, const char* key, const std::string& where) {
  if (!j.contains(key)) return 0;
  if (!j[key].is_number_unsigned()) throw Problem(where + "." + key + " is not a non-negative integer");
  return j[key].get<std::size_t>();
}

std::string name_at(const char* what, std::size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

// Where each buffer view lies in the BIN chunk: (offset, length), each checked against it.
std::vector<std::pair<std::size_t, std::size_t>> check_views(const Json& j, const std::string& bin) {
  const Json& buffers = array_of(j, "buffers", "gltf");
  if (buffers.size() != 1) throw Problem(std::to_string(buffers.size()) + " buffers, expected 1 (the BIN chunk)");
  if (buffers[0].contains("uri")) throw Problem("buffers[0] has a uri: not stored in the BIN chunk");
  const std::size_t length = optional_size(buffers[0], "byteLength", "buffers[0]");
  if (length > bin.size() || bin.size() - length > 3)
    throw Problem("buffers[0].byteLength " + std::to_string(length) + " does not fit the BIN chunk of " + std::to_string(bin.size()) + " bytes");
  std::vector<std::pair<std::size_t, std::size_t>> views;
  const Json& list = array_of(j, "bufferViews", "gltf");
  for (std::size_t v = 0; v < list.size(); ++v) {
    const std::string where = name_at("bufferViews", v);
    index_at(list[v], "buffer", where, 1);
    const std::size_t offset = optional_size(list[v], "byteOffset", where), size = optional_size(list[v], "byteLength", where);
    if (size == 0 || offset > length || size > length - offset)
      throw Problem(where + ": bytes [" + std::to_string(offset) + ", " + std::to_string(offset + size) + ") outside the buffer of " + std::to_string(length));
    views.emplace_back(offset, size);
  }
  return views;
}

struct AccessorInfo {
  int component = 0;
  std::string type;
  std::size_t count = 0;
  bool has_view = false, has_bounds = false;
  std::size_t offset = 0;  // in the BIN chunk
};

std::size_t component_size(int c) {
  switch (c) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
  }
  return 0;
}

std::size_t type_width(const std::string& t) {
  if (t == "SCALAR") return 1;
  if (t == "VEC2") return 2;
  if (t == "VEC3") return 3;
  if (t == "VEC4" || t == "MAT2") return 4;
  return t == "MAT3" ? 9 : t == "MAT4" ? 16 : 0;
}

// Every accessor's elements within its buffer view (and so within the BIN chunk).
std::vector<AccessorInfo> check_accessors(const Json& j, const std::vector<std::pair<std::size_t, std::size_t>>& views) {
  std::vector<AccessorInfo> out;
  const Json& list = array_of(j, "accessors", "gltf");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = name_at("accessors", i);
    AccessorInfo a;
    a.component = list[i].value("componentType", 0);
    a.type = list[i].value("type", std::string());
    a.count = optional_size(list[i], "count", where);
    const std::size_t element = component_size(a.component) * type_width(a.type);
    if (element == 0 || a.count == 0) throw Problem(where + ": bad componentType, type or count");
    a.has_bounds = list[i].contains("min") && list[i].contains("max");
    if (list[i].contains("bufferView")) {
      const auto [offset, length] = views[index_at(list[i], "bufferView", where, views.size())];
      const std::size_t stride = std::max(element, optional_size(j["bufferViews"][list[i]["bufferView"].get<std::size_t>()], "byteStride", where));
      const std::size_t start = optional_size(list[i], "byteOffset", where), need = start + stride * (a.count - 1) + element;
      if (need > length)
        throw Problem(where + ": " + std::to_string(need) + " bytes from its buffer view's start, the view has " + std::to_string(length));
      a.has_view = true;
      a.offset = offset + start;
    }
    out.push_back(a);
  }
  return out;
}

// The frames animation.glb keeps: 0, step, 2 step, ... and the last (gltf_writer.hpp).
std::size_t kept_frames(std::size_t frames, std::size_t step) {
  if (frames == 0) return 0;
  return (frames - 1) / step + 1 + ((frames - 1) % step ? 1 : 0);
}

struct Expect {
  std::size_t targets = 0;  // morph targets per mesh
  std::size_t keys = 0;     // animation keys (kept frames)
};

Expect expected_animation(const Json& j, std::size_t frames) {
  std::size_t step = 1;
  const Json& animations = array_of(j, "animations", "gltf");
  if (!animations.empty() && animations[0].contains("extras")) {
    const Json& extras = animations[0]["extras"];
    step = std::max<std::size_t>(1, optional_size(extras, "frame_step", "animations[0].extras"));
    if (extras.contains("frame_count") && optional_size(extras, "frame_count", "animations[0].extras") != frames)
      throw Problem("animations[0].extras.frame_count is " + extras["frame_count"].dump() + ", report.json has " + std::to_string(frames) + " frames");
  }
  Expect e;
  e.keys = kept_frames(frames, step);
  e.targets = e.keys > 0 ? e.keys - 1 : 0;
  return e;
}

void require_vec3_positions(const AccessorInfo& a, std::size_t vertices, const std::string& where) {
  if (a.component != 5126 || a.type != "VEC3") throw Problem(where + ": POSITION is not float VEC3");
  if (a.count != vertices) throw Problem(where + ": " + std::to_string(a.count) + " vertices, the piece file has " + std::to_string(vertices));
  if (!a.has_bounds) throw Problem(where + ": POSITION accessor without min and max (glTF requires them)");
}

std::vector<Tri> read_triangles(const AccessorInfo& a, const std::string& bin, std::size_t vertices, const std::string& where) {
  if (a.component != 5125 || a.type != "SCALAR" || !a.has_view || a.count % 3)
    throw Problem(where + ": indices are not uint32 triangles in a buffer view");
  std::vector<Tri> out(a.count / 3);
  for (std::size_t i = 0; i < a.count; ++i) {
    const std::uint32_t v = u32_at(bin, a.offset + 4 * i);
    if (v >= vertices) throw Problem(where + ": index " + std::to_string(v) + " out of range (" + std::to_string(vertices) + " vertices)");
    out[i / 3][i % 3] = v;
  }
  return out;
}

// One primitive: positions, morph targets and triangles against the piece file.
void check_primitive(const Json& j, const Json& prim, const std::vector<AccessorInfo>& acc, const std::string& bin,
                     const PieceFile& piece, const Expect& e, const std::string& where) {
  const std::size_t vertices = piece.mesh.positions.size();
  if (!prim.contains("attributes")) throw Problem(where + ": no attributes");
  require_vec3_positions(acc[index_at(prim["attributes"], "POSITION", where + ".attributes", acc.size())], vertices, where);
  const Json& targets = array_of(prim, "targets", where);
  if (targets.size() != e.targets)
    throw Problem(where + ": " + std::to_string(targets.size()) + " morph targets, expected " + std::to_string(e.targets) +
                  " (one per kept frame after the first)");
  for (std::size_t t = 0; t < targets.size(); ++t)
    require_vec3_positions(acc[index_at(targets[t], "POSITION", where + name_at(".targets", t), acc.size())], vertices,
                           where + name_at(".targets", t));
  const std::size_t material = index_at(prim, "material", where, array_of(j, "materials", "gltf").size());
  const bool inside = j["materials"][material].value("name", std::string()) == "inside";
  const std::vector<Tri> faces = read_triangles(acc[index_at(prim, "indices", where, acc.size())], bin, vertices, where);
  if (faces != obj_order(piece, inside ? 1 : 0))
    throw Problem(where + ": its " + std::to_string(faces.size()) + " triangles differ from the " + (inside ? "inside" : "outside") +
                  " faces of " + piece.name);
}

void check_meshes(const Json& j, const std::vector<AccessorInfo>& acc, const std::string& bin, const std::vector<PieceFile>& pieces,
                  const Expect& e) {
  const Json& nodes = array_of(j, "nodes", "gltf");
  if (nodes.size() != pieces.size())
    throw Problem(std::to_string(nodes.size()) + " nodes, report.json has " + std::to_string(pieces.size()) + " pieces");
  const Json& meshes = array_of(j, "meshes", "gltf");
  for (std::size_t p = 0; p < nodes.size(); ++p) {
    char name[32];
    std::snprintf(name, sizeof name, "piece_%03zu", p);
    if (nodes[p].value("name", std::string()) != name) throw Problem(name_at("nodes", p) + " is not named " + name);
    if (!pieces[p].present) continue;  // already reported by piece_files
    const std::size_t m = index_at(nodes[p], "mesh", name_at("nodes", p), meshes.size());
    const Json& prims = array_of(meshes[m], "primitives", name_at("meshes", m));
    if (prims.empty()) throw Problem(name_at("meshes", m) + " has no primitive");
    std::size_t triangles = 0;
    for (std::size_t k = 0; k < prims.size(); ++k) {
      check_primitive(j, prims[k], acc, bin, pieces[p], e, name_at("meshes", m) + name_at(".primitives", k));
      triangles += acc[prims[k]["indices"].get<std::size_t>()].count / 3;
    }
    if (triangles != pieces[p].mesh.triangles.size())
      throw Problem(std::string(name) + ": " + std::to_string(triangles) + " triangles, " + pieces[p].name + " has " +
                    std::to_string(pieces[p].mesh.triangles.size()));
  }
}

// One weights channel per node, keys at the kept frames' times, one weight per target per key.
void check_animation(const Json& j, const std::vector<AccessorInfo>& acc, std::size_t nodes, const Expect& e) {
  const Json& animations = array_of(j, "animations", "gltf");
  if (e.targets == 0) return;
  if (animations.size() != 1) throw Problem(std::to_string(animations.size()) + " animations, expected 1");
  const Json& channels = array_of(animations[0], "channels", "animations[0]");
  const Json& samplers = array_of(animations[0], "samplers", "animations[0]");
  if (channels.size() != nodes) throw Problem(std::to_string(channels.size()) + " animation channels, expected one per node (" + std::to_string(nodes) + ")");
  std::set<std::size_t> animated;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const std::string where = name_at("animations[0].channels", c);
    const Json& target = channels[c].contains("target") ? channels[c]["target"] : Json::object();
    if (target.value("path", std::string()) != "weights" || !animated.insert(index_at(target, "node", where + ".target", nodes)).second)
      throw Problem(where + ": not the one weights channel of a node");
    const Json& sampler = samplers[index_at(channels[c], "sampler", where, samplers.size())];
    const AccessorInfo& input = acc[index_at(sampler, "input", where + ".sampler", acc.size())];
    const AccessorInfo& output = acc[index_at(sampler, "output", where + ".sampler", acc.size())];
    if (input.count != e.keys || !input.has_bounds || input.component != 5126)
      throw Problem(where + ": sampler input has " + std::to_string(input.count) + " float keys" + (input.has_bounds ? "" : " without min/max") +
                    ", expected " + std::to_string(e.keys) + " with min/max");
    const std::size_t per_key = sampler.value("interpolation", std::string("LINEAR")) == "CUBICSPLINE" ? 3 : 1;
    if (output.count != e.keys * e.targets * per_key)
      throw Problem(where + ": sampler output has " + std::to_string(output.count) + " weights, expected " + std::to_string(e.keys * e.targets * per_key));
  }
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  if (!in) throw Problem("cannot be read");
  return bytes.str();
}

}  // namespace

void check_glb(const fs::path& out, const std::vector<PieceFile>& pieces, std::size_t frames, CheckReport& report) {
  try {
    const std::string bytes = read_file(out / "animation.glb");
    const GlbParts parts = split_glb(bytes);
    if (parts.bin.empty()) throw Problem("no BIN chunk");
    const Json j = parse_json(parts.json);
    if (!j.contains("asset") || !j["asset"].is_object() || j["asset"].value("version", std::string()) != "2.0")
      throw Problem("asset.version is not \"2.0\"");
    const std::vector<AccessorInfo> acc = check_accessors(j, check_views(j, parts.bin));
    const Expect e = expected_animation(j, frames);
    check_meshes(j, acc, parts.bin, pieces, e);
    check_animation(j, acc, pieces.size(), e);
    record(report, "glb", {}, std::to_string(pieces.size()) + " nodes, " + std::to_string(e.targets) + " morph targets each, " +
                                  std::to_string(bytes.size()) + " bytes");
  } catch (const Problem& p) {
    record(report, "glb", {"animation.glb: " + std::string(p.what())}, "");
  } catch (const Json::exception& e) {  // a member of the wrong JSON type
    record(report, "glb", {"animation.glb: JSON chunk: " + std::string(e.what())}, "");
  }
}

}  // namespace fracref::check_detail
