// animation.glb: the pieces, their normals and material coordinates, and their animation as node
// transforms (rigid pieces) or morph targets (see gltf_writer.hpp).
#include "animate/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>

#include "animate/animate_internal.hpp"
#include "animate/gltf_internal.hpp"
#include "animate/piece_surface.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using animate_detail::LocalFaces;
using animate_detail::Tri;
using namespace gltf_detail;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

std::string numbered(const char* format, std::size_t n) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, n);
  return buffer;
}

// What every piece's mesh is made of, before the data is written.
struct PieceMesh {
  SplitPiece split;
  std::vector<glm::dvec3> base;  // per split id: the mesh's POSITION (rest less pivot, or frame 0)
  std::vector<float> base_float;
};

// Per piece, its accessors.
struct MeshRefs {
  std::size_t position = 0, normal = 0, texcoord = 0, material = 0;
  std::optional<std::size_t> color;  // COLOR_0 of the fracture faces, when the options give colours
  std::optional<std::size_t> exterior, inside;
  std::vector<std::size_t> targets;  // deforming pieces: one POSITION accessor per kept frame after the first
  std::size_t translation = 0, rotation = 0;  // rigid pieces with an animation: sampler outputs
};

// The material-space box every texture coordinate is taken in.
struct MaterialBox {
  glm::dvec3 lo{0.0};
  double diagonal = 1.0;
};

MaterialBox material_box(const PieceSet& pieces) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::dvec3& x : pieces.positions) lo = glm::min(lo, x), hi = glm::max(hi, x);
  MaterialBox b;
  if (pieces.positions.empty()) return b;
  b.lo = lo;
  const double d = glm::length(hi - lo);
  b.diagonal = d > 0.0 ? d : 1.0;
  return b;
}

std::vector<std::vector<glm::dvec3>> rest_positions(const PieceSet& pieces, const PieceLayout& layout) {
  std::vector<std::vector<glm::dvec3>> rest(layout.vertices.size());
  for (std::size_t p = 0; p < rest.size(); ++p)
    for (std::uint32_t v : layout.vertices[p]) rest[p].push_back(pieces.positions[v]);
  return rest;
}

PieceMesh piece_mesh(const LocalFaces& faces, std::size_t p, const std::vector<glm::dvec3>& local) {
  PieceMesh m;
  if (local.empty() || faces.faces[p].empty()) throw RunError("animation.glb: piece " + std::to_string(p) + " has no triangle");
  m.split = split_piece(faces.faces[p], faces.inside[p], local);
  for (std::size_t i = 0; i < m.split.normals.size(); ++i) {
    m.base.push_back(local[m.split.original(i)]);
    for (int k = 0; k < 3; ++k) m.base_float.push_back(float(m.base.back()[k]));
  }
  return m;
}

std::vector<float> floats_of(const std::vector<glm::dvec3>& v) {
  std::vector<float> out;
  for (const glm::dvec3& x : v) out.insert(out.end(), {float(x.x), float(x.y), float(x.z)});
  return out;
}

std::size_t add_indices(Glb& g, const std::vector<Tri>& faces) {
  Accessor a;
  a.component = kUnsignedInt;
  const std::size_t begin = g.bin.size();
  for (const Tri& t : faces)
    for (std::uint32_t v : t) put_u32(g.bin, v), ++a.count;
  return g.add(std::move(a), begin, kElementArrayBuffer);
}

// POSITION, NORMAL, TEXCOORD_0, _MATERIAL_POSITION, COLOR_0 when coloured, and the two index
// lists of one piece.
MeshRefs add_mesh(Glb& g, const PieceMesh& m, const std::vector<glm::dvec3>& material, const MaterialBox& box,
                  const GltfOptions& o) {
  MeshRefs r;
  r.position = add_floats(g, m.base_float, 3, "VEC3", true, kArrayBuffer);
  r.normal = add_floats(g, floats_of(m.split.normals), 3, "VEC3", false, kArrayBuffer);
  std::vector<float> uv;
  std::vector<glm::dvec3> mat;
  for (std::size_t i = 0; i < m.split.normals.size(); ++i) {
    mat.push_back(material[m.split.original(i)]);
    const glm::dvec2 t = box_texcoord(mat.back(), m.split.normals[i], box.lo, box.diagonal);
    uv.insert(uv.end(), {float(t.x), float(t.y)});
  }
  r.texcoord = add_floats(g, uv, 2, "VEC2", false, kArrayBuffer);
  r.material = add_floats(g, floats_of(mat), 3, "VEC3", false, kArrayBuffer);
  if (o.inside_color) {
    std::vector<float> rgb;
    for (const glm::dvec3& x : mat) {
      const glm::vec3 c = glm::clamp(o.inside_color(x), glm::vec3(0.0f), glm::vec3(1.0f));
      rgb.insert(rgb.end(), {c.r, c.g, c.b});
    }
    r.color = add_floats(g, rgb, 3, "VEC3", false, kArrayBuffer);
  }
  if (!m.split.outside.empty()) r.exterior = add_indices(g, m.split.outside);
  if (!m.split.inside.empty()) r.inside = add_indices(g, m.split.inside);
  return r;
}

// A deforming piece's morph target for a frame: deltas from the float base, per split id.
void add_deforming_target(Glb& g, MeshRefs& r, const PieceMesh& m, const glm::dvec3* x) {
  std::vector<float> delta;
  delta.reserve(m.base_float.size());
  for (std::size_t i = 0; i < m.split.normals.size(); ++i)
    for (int k = 0; k < 3; ++k) delta.push_back(float(x[m.split.original(i)][k] - double(m.base_float[3 * i + std::size_t(k)])));
  r.targets.push_back(add_target(g, delta));
}

void add_rigid_keys(Glb& g, MeshRefs& r, const PieceMotion& m, const std::vector<std::size_t>& kept) {
  std::vector<float> t, q;
  for (std::size_t f : kept) {
    t.insert(t.end(), {m.translation[f].x, m.translation[f].y, m.translation[f].z});
    q.insert(q.end(), {m.rotation[f].x, m.rotation[f].y, m.rotation[f].z, m.rotation[f].w});
  }
  r.translation = add_floats(g, t, 3, "VEC3", false, 0);
  r.rotation = add_floats(g, q, 4, "VEC4", false, 0);
}

// Frame times (with bounds), and per time the weights of every target: the unit vector of the frame's target.
std::pair<std::size_t, std::size_t> add_keys(Glb& g, const std::vector<std::size_t>& kept, double fps, bool weights) {
  std::vector<float> times, w;
  for (std::size_t j = 0; j < kept.size(); ++j) {
    times.push_back(float(double(kept[j]) / fps));
    for (std::size_t t = 1; weights && t < kept.size(); ++t) w.push_back(t == j ? 1.0f : 0.0f);
  }
  const std::size_t input = add_floats(g, times, 1, "SCALAR", true, 0);
  return {input, weights ? add_floats(g, w, 1, "SCALAR", false, 0) : 0};
}

// The file's size, but for the fixed part of the JSON (an accessor, view and channel take under
// 256 bytes of JSON per piece and kept frame).
std::size_t data_bytes(std::size_t kept, std::size_t deforming_vertices, std::size_t rigid, std::size_t fixed, std::size_t pieces) {
  const std::size_t weights = deforming_vertices ? 4 * kept * (kept - 1) : 0;
  return 12 * deforming_vertices * kept + 28 * rigid * kept + 4 * kept + weights + fixed + 256 * pieces * kept;
}

// gltf_kept_frames(frames, step).size(), without building the list.
std::size_t kept_count(std::size_t frames, std::size_t step) {
  return frames == 0 ? 0 : (frames - 1) / step + 1 + ((frames - 1) % step ? 1 : 0);
}

GltfSummary plan(std::size_t frames, const std::vector<PieceMesh>& meshes, const std::vector<PieceMotion>& motion,
                 const GltfOptions& o) {
  std::size_t fixed = 0, deforming = 0, rigid = 0;
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    const std::size_t n = meshes[p].split.normals.size();
    // Per vertex: POSITION, NORMAL, _MATERIAL_POSITION 12 bytes each, TEXCOORD_0 8, COLOR_0 12.
    fixed += (o.inside_color ? 56 : 44) * n + 12 * (meshes[p].split.outside.size() + meshes[p].split.inside.size());
    motion[p].rigid ? ++rigid : deforming += n;
  }
  GltfSummary s;
  s.frame_count = frames;
  s.rigid_pieces = rigid;
  for (s.frame_step = 1;; ++s.frame_step) {
    s.frames_kept = kept_count(frames, s.frame_step);
    if (data_bytes(s.frames_kept, deforming, rigid, fixed, meshes.size()) <= o.max_bytes) break;
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

void write_reals(JsonWriter& w, const char* key, const float* v, int n) {
  w.key(key).open('[');
  for (int k = 0; k < n; ++k) w.real(double(v[k]));
  w.close(']');
}

// One node per piece; a rigid piece's node holds its frame-0 pose, for readers without animation.
void write_nodes(JsonWriter& w, const std::vector<PieceMotion>& motion) {
  w.key("scenes").open('[').open('{').key("name").str("fracture").key("nodes").open('[');
  for (std::size_t p = 0; p < motion.size(); ++p) w.integer(p);
  w.close(']').close('}').close(']');
  w.key("nodes").open('[');
  for (std::size_t p = 0; p < motion.size(); ++p) {
    w.open('{').key("name").str(numbered("piece_%03zu", p)).key("mesh").integer(p);
    if (motion[p].rigid) {
      write_reals(w, "translation", &motion[p].translation[0].x, 3);
      write_reals(w, "rotation", &motion[p].rotation[0].x, 4);
    }
    w.close('}');
  }
  w.close(']');
}

void write_primitive(JsonWriter& w, const MeshRefs& m, std::size_t indices, int material, bool exterior_colored) {
  w.open('{').key("attributes").open('{').key("POSITION").integer(m.position).key("NORMAL").integer(m.normal);
  if (material == 1) w.key("TEXCOORD_0").integer(m.texcoord);
  if (m.color && (material == 1 || exterior_colored)) w.key("COLOR_0").integer(*m.color);
  w.key("_MATERIAL_POSITION").integer(m.material).close('}');
  w.key("indices").integer(indices).key("material").integer(std::uint64_t(material)).key("mode").integer(4);
  if (!m.targets.empty()) {
    w.key("targets").open('[');
    for (std::size_t t : m.targets) w.open('{').key("POSITION").integer(t).close('}');
    w.close(']');
  }
  w.close('}');
}

void write_meshes(JsonWriter& w, const std::vector<MeshRefs>& meshes, const std::vector<std::size_t>& kept,
                  bool exterior_colored) {
  w.key("meshes").open('[');
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    w.open('{').key("name").str(numbered("piece_%03zu", p)).key("primitives").open('[');
    if (meshes[p].exterior) write_primitive(w, meshes[p], *meshes[p].exterior, 0, exterior_colored);
    if (meshes[p].inside) write_primitive(w, meshes[p], *meshes[p].inside, 1, exterior_colored);
    w.close(']');
    if (!meshes[p].targets.empty()) {
      w.key("extras").open('{').key("targetNames").open('[');
      for (std::size_t j = 1; j < kept.size(); ++j) w.str(numbered("frame_%04zu", kept[j]));
      w.close(']').close('}');
    }
    w.close('}');
  }
  w.close(']');
}

// The colours of frames.mtl (outside grey, inside warm), as linear base colours; white where
// the faces carry their own colours (COLOR_0, which the base colour multiplies).
void write_materials(JsonWriter& w, bool inside_colored, bool exterior_colored) {
  w.key("materials").open('[');
  constexpr std::array<double, 3> kWhite{1.0, 1.0, 1.0};
  const std::array<double, 3> inside = inside_colored ? kWhite : std::array<double, 3>{0.85, 0.55, 0.35};
  const std::array<double, 3> exterior = exterior_colored ? kWhite : std::array<double, 3>{0.8, 0.8, 0.8};
  const std::pair<const char*, std::array<double, 3>> materials[] = {{"exterior", exterior}, {"inside", inside}};
  for (const auto& [name, rgb] : materials) {
    w.open('{').key("name").str(name).key("pbrMetallicRoughness").open('{').key("baseColorFactor").open('[');
    for (double c : rgb) w.real(c);
    w.real(1.0).close(']').key("metallicFactor").real(0.0).key("roughnessFactor").real(0.8).close('}');
    w.key("doubleSided").boolean(false).close('}');
  }
  w.close(']');
}

void write_accessor(JsonWriter& w, const Accessor& a) {
  w.open('{');
  if (a.view >= 0) w.key("bufferView").integer(std::uint64_t(a.view));
  w.key("componentType").integer(std::uint64_t(a.component)).key("count").integer(a.count).key("type").str(a.type);
  if (!a.min.empty()) write_reals(w, "min", a.min.data(), int(a.min.size())), write_reals(w, "max", a.max.data(), int(a.max.size()));
  if (a.sparse_count) {
    w.key("sparse").open('{').key("count").integer(a.sparse_count);
    w.key("indices").open('{').key("bufferView").integer(std::uint64_t(a.sparse_indices)).key("componentType").integer(kUnsignedInt).close('}');
    w.key("values").open('{').key("bufferView").integer(std::uint64_t(a.sparse_values)).close('}').close('}');
  }
  w.close('}');
}

void write_accessors(JsonWriter& w, const Glb& g) {
  w.key("accessors").open('[');
  for (const Accessor& a : g.accessors) write_accessor(w, a);
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

// Channels in piece order: a rigid piece's translation and rotation, a deforming piece's weights.
void write_animation(JsonWriter& w, const std::vector<MeshRefs>& meshes, const std::vector<PieceMotion>& motion,
                     std::pair<std::size_t, std::size_t> keys, const GltfSummary& s) {
  std::vector<std::pair<std::size_t, const char*>> channels;  // (output accessor, path), per node
  std::vector<std::size_t> nodes;
  for (std::size_t p = 0; p < meshes.size(); ++p) {
    if (motion[p].rigid) channels.push_back({meshes[p].translation, "translation"}), channels.push_back({meshes[p].rotation, "rotation"});
    else channels.push_back({keys.second, "weights"});
    nodes.resize(channels.size(), p);
  }
  w.key("animations").open('[').open('{').key("name").str("fracture").key("channels").open('[');
  for (std::size_t c = 0; c < channels.size(); ++c)
    w.open('{').key("sampler").integer(c).key("target").open('{').key("node").integer(nodes[c]).key("path").str(channels[c].second).close('}').close('}');
  w.close(']').key("samplers").open('[');
  for (const auto& [output, path] : channels)
    w.open('{').key("input").integer(keys.first).key("interpolation").str("LINEAR").key("output").integer(output).close('}');
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

// The meshes: a rigid piece on its rest vertices less its pivot, a deforming one on frame 0.
std::vector<PieceMesh> build_meshes(const FrameSource& src, const LocalFaces& faces, const std::vector<std::vector<glm::dvec3>>& rest,
                                    const std::vector<PieceMotion>& motion) {
  const bool deforming = std::any_of(motion.begin(), motion.end(), [](const PieceMotion& m) { return !m.rigid; });
  const std::vector<glm::dvec3> x0 = deforming ? frame_positions(src, 0) : std::vector<glm::dvec3>{};
  std::vector<PieceMesh> meshes;
  for (std::size_t p = 0; p < rest.size(); ++p) {
    std::vector<glm::dvec3> local = rest[p];
    for (std::size_t i = 0; i < local.size(); ++i) local[i] = motion[p].rigid ? local[i] - motion[p].pivot : x0[src.layout.offsets[p] + i];
    meshes.push_back(piece_mesh(faces, p, local));
  }
  return meshes;
}

void add_animation_data(Glb& g, std::vector<MeshRefs>& refs, const FrameSource& src, const std::vector<PieceMesh>& meshes,
                        const std::vector<PieceMotion>& motion, const std::vector<std::size_t>& kept) {
  const bool deforming = std::any_of(motion.begin(), motion.end(), [](const PieceMotion& m) { return !m.rigid; });
  for (std::size_t j = 1; deforming && j < kept.size(); ++j) {
    const std::vector<glm::dvec3> x = frame_positions(src, kept[j]);
    for (std::size_t p = 0; p < refs.size(); ++p)
      if (!motion[p].rigid) add_deforming_target(g, refs[p], meshes[p], x.data() + src.layout.offsets[p]);
  }
  for (std::size_t p = 0; p < refs.size() && kept.size() > 1; ++p)
    if (motion[p].rigid) add_rigid_keys(g, refs[p], motion[p], kept);
}

std::string encode(const PieceSet& pieces, const FrameSource& src, const GltfOptions& o, GltfSummary* summary) {
  if (src.count == 0) throw RunError("animation.glb: the animation has no frame");
  if (!(src.fps > 0.0) || !std::isfinite(src.fps)) throw RunError("animation.glb: fps " + std::to_string(src.fps) + " is not > 0");
  const LocalFaces faces = animate_detail::local_faces(pieces, src.layout, "animation.glb");
  const std::vector<std::vector<glm::dvec3>> rest = rest_positions(pieces, src.layout);
  const MaterialBox box = material_box(pieces);
  const std::vector<PieceMotion> motion = analyse_motion(src, rest, o.rigid_tolerance * box.diagonal);
  const std::vector<PieceMesh> meshes = build_meshes(src, faces, rest, motion);
  GltfSummary s = plan(src.count, meshes, motion, o);
  const std::vector<std::size_t> kept = gltf_kept_frames(src.count, s.frame_step);
  Glb g;
  std::vector<MeshRefs> refs;
  for (std::size_t p = 0; p < meshes.size(); ++p) refs.push_back(add_mesh(g, meshes[p], rest[p], box, o));
  add_animation_data(g, refs, src, meshes, motion, kept);
  std::pair<std::size_t, std::size_t> keys;
  if (kept.size() > 1) keys = add_keys(g, kept, src.fps, s.rigid_pieces < meshes.size());
  JsonWriter w;
  w.open('{');
  write_asset(w);
  write_nodes(w, motion);
  const bool exterior_colored = o.inside_color && o.color_exterior;
  write_meshes(w, refs, kept, exterior_colored);
  write_materials(w, bool(o.inside_color), exterior_colored);
  write_accessors(w, g);
  if (kept.size() > 1) write_animation(w, refs, motion, keys, s);
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
  const gltf_detail::FrameSource src{result.layout, result.frames.size(), result.fps, [&](std::size_t f) { return result.frames[f]; }};
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
  const gltf_detail::FrameSource src{transfer.layout, transfer.frame_count, animation.fps,
                        [&](std::size_t f) { return transfer_frame(transfer, animation, f); }};
  GltfSummary s;
  write_file_atomic(file, encode(pieces, src, options, &s));
  return s;
}

}  // namespace fracref
