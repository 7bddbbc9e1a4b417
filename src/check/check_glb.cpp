// The glb check: animation.glb read back with its own GLB reader (not the writer's code) and held
// against glTF 2.0 and against the piece files and report.json.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "scene/json_strict.hpp"

#include "check/check_glb_internal.hpp"

namespace fracref::check_detail {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Tri = std::array<std::uint32_t, 3>;

constexpr std::uint32_t kMagic = 0x46546C67, kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;

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

}  // namespace

std::uint32_t u32_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | std::uint8_t(bytes[offset + std::size_t(k)]);
  return v;
}

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

namespace {

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

// A sparse accessor's indices (strictly increasing, below count) and values within their views.
void check_sparse(const Json& sp, const std::vector<std::pair<std::size_t, std::size_t>>& views, std::size_t element,
                  const std::string& where, AccessorInfo& a) {
  a.sparse_count = optional_size(sp, "count", where + ".sparse");
  const Json& idx = sp.contains("indices") ? sp["indices"] : Json::object();
  const Json& val = sp.contains("values") ? sp["values"] : Json::object();
  a.sparse_component = idx.value("componentType", 0);
  const std::size_t isize = component_size(a.sparse_component);
  if (a.sparse_count == 0 || a.sparse_count > a.count || (isize != 1 && isize != 2 && isize != 4) || a.sparse_component == 5120 ||
      a.sparse_component == 5122)
    throw Problem(where + ".sparse: bad count or index componentType");
  const auto [ioff, ilen] = views[index_at(idx, "bufferView", where + ".sparse.indices", views.size())];
  const auto [voff, vlen] = views[index_at(val, "bufferView", where + ".sparse.values", views.size())];
  const std::size_t istart = optional_size(idx, "byteOffset", where), vstart = optional_size(val, "byteOffset", where);
  if (istart + isize * a.sparse_count > ilen || vstart + element * a.sparse_count > vlen)
    throw Problem(where + ".sparse: indices or values run past their buffer view");
  a.sparse_indices = ioff + istart, a.sparse_values = voff + vstart;
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
    if (list[i].contains("sparse")) check_sparse(list[i]["sparse"], views, component_size(a.component) * type_width(a.type), where, a);
    out.push_back(a);
  }
  return out;
}

std::uint32_t index_value(const std::string& bin, std::size_t at, int component) {
  if (component == 5121) return std::uint8_t(bin[at]);
  if (component == 5123) return std::uint32_t(std::uint8_t(bin[at])) | std::uint32_t(std::uint8_t(bin[at + 1])) << 8;
  return u32_at(bin, at);
}

}  // namespace

std::vector<double> float_values(const GlbFile& g, std::size_t index, std::size_t width, const std::string& where) {
  const AccessorInfo& a = g.acc.at(index);
  if (a.component != 5126 || type_width(a.type) != width) throw Problem(where + ": not a float accessor of " + std::to_string(width) + " components");
  std::vector<double> out(a.count * width, 0.0);
  auto at = [&](std::size_t offset) { return double(std::bit_cast<float>(u32_at(g.bin, offset))); };
  if (a.has_view)
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = at(a.offset + 4 * i);
  std::size_t previous = 0;
  for (std::size_t k = 0; k < a.sparse_count; ++k) {
    const std::uint32_t i = index_value(g.bin, a.sparse_indices + k * component_size(a.sparse_component), a.sparse_component);
    if (i >= a.count || (k > 0 && i <= previous)) throw Problem(where + ": sparse indices not increasing or out of range");
    previous = i;
    for (std::size_t c = 0; c < width; ++c) out[i * width + c] = at(a.sparse_values + 4 * (k * width + c));
  }
  return out;
}

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  if (!in) throw Problem("cannot be read");
  return bytes.str();
}

}  // namespace

void check_glb(const fs::path& out, const std::vector<PieceFile>& pieces, std::size_t frames, const FrameReader& frame,
               CheckReport& report) {
  GlbFile g;
  try {
    const std::string bytes = read_file(out / "animation.glb");
    const GlbParts parts = split_glb(bytes);
    if (parts.bin.empty()) throw Problem("no BIN chunk");
    g.j = parse_json(parts.json);
    g.bin = parts.bin;
    if (!g.j.contains("asset") || !g.j["asset"].is_object() || g.j["asset"].value("version", std::string()) != "2.0")
      throw Problem("asset.version is not \"2.0\"");
    g.acc = check_accessors(g.j, check_views(g.j, g.bin));
    const GlbSummary s = check_glb_pieces(g, pieces, frames);
    record(report, "glb", {}, std::to_string(pieces.size()) + " nodes (" + std::to_string(s.rigid) + " moved by node transforms, " +
                                  std::to_string(s.deforming) + " by " + std::to_string(s.targets) + " morph targets each), " +
                                  std::to_string(bytes.size()) + " bytes");
  } catch (const Problem& p) {
    record(report, "glb", {"animation.glb: " + std::string(p.what())}, "");
    return;
  } catch (const Json::exception& e) {  // a member of the wrong JSON type
    record(report, "glb", {"animation.glb: JSON chunk: " + std::string(e.what())}, "");
    return;
  }
  if (!frame) {
    record_skipped(report, "glb_frames", "no frames/ to compare with (the scene's output.frames is false), or they failed their check");
    return;
  }
  try {
    check_glb_frames(g, pieces, frames, frame, report);
  } catch (const Problem& p) {
    record(report, "glb_frames", {"animation.glb: " + std::string(p.what())}, "");
  }
}

}  // namespace fracref::check_detail
