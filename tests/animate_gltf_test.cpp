// animation.glb: two tetrahedra sharing a fracture face, three frames in which the second one
// moves rigidly (or stretches). The GLB is parsed back here, independently of the writer: the
// container (magic, version, length, padded chunks), the JSON (nodes, primitives, split rim
// vertices, normals, material coordinates, accessors and their bounds), node transforms of the
// rigid pieces and morph targets (dense and sparse) of the deforming one reproducing every frame,
// the animation keys, decimation under a byte budget, determinism and the errors; and the
// rigid fit itself.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "animate/gltf_writer.hpp"
#include "animate/piece_surface.hpp"
#include "animate/rigid_fit.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Json = nlohmann::json;

std::uint32_t u32_at(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | std::uint8_t(bytes.at(offset + std::size_t(k)));
  return v;
}

// A GLB split into its parts, with the container's invariants asserted on the way.
struct Glb {
  std::uint32_t magic = 0, version = 0, length = 0;
  std::string json_text, bin;
  Json json;
};

Glb parse_glb(const std::string& bytes) {
  Glb g;
  g.magic = u32_at(bytes, 0), g.version = u32_at(bytes, 4), g.length = u32_at(bytes, 8);
  const std::uint32_t json_length = u32_at(bytes, 12);
  EXPECT_EQ(u32_at(bytes, 16), 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(json_length % 4, 0u);
  g.json_text = bytes.substr(20, json_length);
  const std::size_t bin_at = 20 + json_length;
  const std::uint32_t bin_length = u32_at(bytes, bin_at);
  EXPECT_EQ(u32_at(bytes, bin_at + 4), 0x004E4942u);  // "BIN\0"
  EXPECT_EQ(bin_length % 4, 0u);
  EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());
  g.bin = bytes.substr(bin_at + 8, bin_length);
  g.json = Json::parse(g.json_text);
  return g;
}

double value_at(const Glb& g, std::size_t offset, bool is_float) {
  const std::uint32_t raw = u32_at(g.bin, offset);
  float f;
  std::memcpy(&f, &raw, 4);
  return is_float ? double(f) : double(raw);
}

std::size_t width_of(const Json& a) {
  const std::string t = a["type"];
  return t == "VEC4" ? 4 : t == "VEC3" ? 3 : t == "VEC2" ? 2 : 1;
}

// The values of a float or uint32 accessor (zeros without a buffer view, sparse values applied), bounds-checked.
std::vector<double> accessor_values(const Glb& g, std::size_t index) {
  const Json& a = g.json["accessors"][index];
  const std::size_t width = width_of(a);
  const bool is_float = a["componentType"] == 5126;
  std::vector<double> out(a["count"].get<std::size_t>() * width, 0.0);
  if (a.contains("bufferView")) {
    const Json& view = g.json["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t offset = view["byteOffset"].get<std::size_t>();
    EXPECT_EQ(view["byteLength"].get<std::size_t>(), out.size() * 4);
    EXPECT_LE(offset + out.size() * 4, g.bin.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = value_at(g, offset + 4 * i, is_float);
  }
  if (!a.contains("sparse")) return out;
  const Json& sp = a["sparse"];
  const std::size_t at_i = g.json["bufferViews"][sp["indices"]["bufferView"].get<std::size_t>()]["byteOffset"];
  const std::size_t at_v = g.json["bufferViews"][sp["values"]["bufferView"].get<std::size_t>()]["byteOffset"];
  for (std::size_t k = 0; k < sp["count"].get<std::size_t>(); ++k) {
    const std::size_t i = std::size_t(value_at(g, at_i + 4 * k, false));
    for (std::size_t c = 0; c < width; ++c) out[i * width + c] = value_at(g, at_v + 4 * (k * width + c), true);
  }
  return out;
}

// Node p's output of its channel `path` at key j, or empty.
std::vector<double> channel_at(const Glb& g, std::size_t node, const std::string& path, std::size_t j) {
  if (!g.json.contains("animations")) return {};
  const Json& anim = g.json["animations"][0];
  for (const Json& c : anim["channels"])
    if (c["target"]["node"] == node && c["target"]["path"] == path) {
      const Json& sampler = anim["samplers"][c["sampler"].get<std::size_t>()];
      const std::vector<double> all = accessor_values(g, sampler["output"]);
      const std::size_t n = all.size() / accessor_values(g, sampler["input"]).size();
      return std::vector<double>(all.begin() + std::ptrdiff_t(j * n), all.begin() + std::ptrdiff_t((j + 1) * n));
    }
  return {};
}

// Piece p's first n vertices at key j: morph weights and node translation and rotation applied.
std::vector<glm::dvec3> positions_at(const Glb& g, std::size_t p, std::size_t n, std::size_t j) {
  const Json& prim = g.json["meshes"][p]["primitives"][0];
  std::vector<double> x = accessor_values(g, prim["attributes"]["POSITION"]);
  const std::vector<double> w = channel_at(g, p, "weights", j);
  for (std::size_t t = 0; t < w.size(); ++t) {
    const std::vector<double> d = accessor_values(g, prim["targets"][t]["POSITION"]);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += w[t] * d[i];
  }
  const Json& node = g.json["nodes"][p];
  std::vector<double> t = channel_at(g, p, "translation", j), r = channel_at(g, p, "rotation", j);
  if (t.empty()) t = node.value("translation", std::vector<double>{0, 0, 0});
  if (r.empty()) r = node.value("rotation", std::vector<double>{0, 0, 0, 1});
  const glm::dmat3 rot = glm::mat3_cast(glm::dquat(r[3], r[0], r[1], r[2]));
  std::vector<glm::dvec3> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(glm::dvec3(t[0], t[1], t[2]) + rot * glm::dvec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]));
  return out;
}

// Tetrahedron A = (0, 1, 2, 3) and B = (1, 2, 3, 4) share the fracture face (1, 2, 3).
PieceSet two_tets() {
  PieceSet set;
  set.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  set.pieces.resize(2);
  set.pieces[0].triangles = {{1, 2, 3}, {0, 2, 1}, {0, 1, 3}, {0, 3, 2}};
  set.pieces[0].inside = {1, 0, 0, 0};
  set.pieces[1].triangles = {{1, 2, 4}, {1, 3, 2}, {2, 3, 4}, {3, 1, 4}};
  set.pieces[1].inside = {0, 1, 0, 0};
  return set;
}

// Frame t: piece 0 still; piece 1 turned by 0.3 t radians about z and moved by 0.5 t along x,
// or, when `stretch`, stretched by 1 + 0.2 t along z (its vertices at z = 0 stay).
AnimationResult three_frames(const PieceSet& set, std::size_t frames = 3, bool stretch = false) {
  AnimationResult r;
  r.layout.vertices = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  r.layout.offsets = {0, 4, 8};
  r.fps = 24.0;
  for (std::size_t t = 0; t < frames; ++t) {
    const double a = 0.3 * double(t), c = std::cos(a), s = std::sin(a);
    std::vector<glm::dvec3> x;
    for (std::uint32_t v : r.layout.vertices[0]) x.push_back(set.positions[v]);
    for (std::uint32_t v : r.layout.vertices[1]) {
      const glm::dvec3 p = set.positions[v];
      if (stretch) x.push_back({p.x, p.y, p.z * (1.0 + 0.2 * double(t))});
      else x.push_back({c * p.x - s * p.y + 0.5 * double(t), s * p.x + c * p.y, p.z + 0.1});
    }
    r.frames.push_back(x);
  }
  return r;
}

class AnimateGltf : public ::testing::Test {
 protected:
  PieceSet set = two_tets();
  AnimationResult result = three_frames(set);
  AnimationResult stretched = three_frames(set, 3, true);
};

TEST_F(AnimateGltf, ContainerHeaderAndChunksArePaddedAndSized) {
  GltfSummary s;
  const std::string bytes = encode_animation_glb(set, result, {}, &s);
  const Glb g = parse_glb(bytes);
  EXPECT_EQ(g.magic, 0x46546C67u);
  EXPECT_EQ(g.version, 2u);
  EXPECT_EQ(g.length, bytes.size());
  EXPECT_EQ(s.bytes, bytes.size());
  EXPECT_EQ(bytes.size() % 4, 0u);
  EXPECT_EQ(g.json_text.find_last_not_of(' ') + 1, Json::parse(g.json_text).dump().size());  // padded with spaces
  EXPECT_EQ(g.json["asset"]["version"], "2.0");
  EXPECT_EQ(g.json["asset"]["generator"], "fracref");
  EXPECT_EQ(g.json["buffers"][0]["byteLength"].get<std::size_t>(), g.bin.size());
  EXPECT_EQ(s.frame_count, 3u);
  EXPECT_EQ(s.frame_step, 1u);
  EXPECT_EQ(s.frames_kept, 3u);
  EXPECT_EQ(s.rigid_pieces, 2u);
  EXPECT_FALSE(s.over_budget);
}

TEST_F(AnimateGltf, NodesMeshesAndPrimitivesFollowThePiecesWithRimCopies) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  ASSERT_EQ(g.json["nodes"].size(), 2u);
  EXPECT_EQ(g.json["nodes"][1]["name"], "piece_001");
  EXPECT_EQ(g.json["meshes"][1]["name"], "piece_001");
  EXPECT_EQ(g.json["nodes"][1]["mesh"], 1);
  EXPECT_EQ(g.json["scenes"][0]["nodes"], Json::array({0, 1}));
  EXPECT_EQ(g.json["materials"][0]["name"], "exterior");
  EXPECT_EQ(g.json["materials"][1]["name"], "inside");
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prims = g.json["meshes"][p]["primitives"];
    ASSERT_EQ(prims.size(), 2u);
    EXPECT_EQ(prims[0]["material"], 0);
    EXPECT_EQ(prims[1]["material"], 1);
    for (const char* a : {"POSITION", "NORMAL", "_MATERIAL_POSITION"}) EXPECT_EQ(prims[0]["attributes"][a], prims[1]["attributes"][a]);
    EXPECT_FALSE(prims[0]["attributes"].contains("TEXCOORD_0"));
    EXPECT_EQ(accessor_values(g, prims[1]["attributes"]["TEXCOORD_0"]).size(), 14u);
    EXPECT_EQ(accessor_values(g, prims[0]["attributes"]["POSITION"]).size(), 21u);  // 4 vertices and 3 rim copies
    EXPECT_FALSE(prims[0].contains("targets"));  // rigid
  }
  // Piece 1's faces on its local vertices (1, 2, 3, 4) -> (0, 1, 2, 3): outside first, then
  // inside on the rim copies 4, 5, 6 of 0, 1, 2.
  const Json& prims = g.json["meshes"][1]["primitives"];
  EXPECT_EQ(accessor_values(g, prims[0]["indices"]), (std::vector<double>{0, 1, 3, 1, 2, 3, 2, 0, 3}));
  EXPECT_EQ(accessor_values(g, prims[1]["indices"]), (std::vector<double>{4, 6, 5}));
  const std::vector<double> m = accessor_values(g, prims[0]["attributes"]["_MATERIAL_POSITION"]);
  EXPECT_EQ(std::vector<double>(m.begin() + 12, m.begin() + 15), (std::vector<double>{1, 0, 0}));  // copy of local 0
}

TEST_F(AnimateGltf, FractureFacesCarryTheColoursAskedForOnAWhiteBase) {
  const Glb plain = parse_glb(encode_animation_glb(set, result));
  EXPECT_FALSE(plain.json["meshes"][0]["primitives"][1]["attributes"].contains("COLOR_0"));
  EXPECT_EQ(plain.json["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"][0], 0.85);
  GltfOptions o;
  // A colour that shows where it was taken: the material position, clamped into [0, 1].
  o.inside_color = [](const glm::dvec3& p) { return glm::vec3(p) * 0.5f + glm::vec3(0.25f); };
  const Glb g = parse_glb(encode_animation_glb(set, result, o));
  EXPECT_EQ(g.json["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"], Json::array({1, 1, 1, 1}));
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prims = g.json["meshes"][p]["primitives"];
    EXPECT_FALSE(prims[0]["attributes"].contains("COLOR_0"));  // the exterior keeps its grey
    const std::vector<double> c = accessor_values(g, prims[1]["attributes"]["COLOR_0"]);
    const std::vector<double> m = accessor_values(g, prims[1]["attributes"]["_MATERIAL_POSITION"]);
    ASSERT_EQ(c.size(), m.size());
    for (std::size_t i = 0; i < c.size(); ++i) EXPECT_FLOAT_EQ(float(c[i]), std::clamp(float(m[i]) * 0.5f + 0.25f, 0.0f, 1.0f));
  }
}

TEST_F(AnimateGltf, ExteriorFacesCarryTheColoursTooWhenAsked) {
  GltfOptions o;
  o.inside_color = [](const glm::dvec3&) { return glm::vec3(0.2f, 0.4f, 0.6f); };
  o.color_exterior = true;
  const Glb g = parse_glb(encode_animation_glb(set, result, o));
  EXPECT_EQ(g.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"], Json::array({1, 1, 1, 1}));
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prims = g.json["meshes"][p]["primitives"];
    ASSERT_TRUE(prims[0]["attributes"].contains("COLOR_0"));
    EXPECT_EQ(prims[0]["attributes"]["COLOR_0"], prims[1]["attributes"]["COLOR_0"]);  // one array, both materials
  }
  o.inside_color = nullptr;  // nothing to colour with: the flag alone changes nothing
  const Glb plain = parse_glb(encode_animation_glb(set, result, o));
  EXPECT_FALSE(plain.json["meshes"][0]["primitives"][0]["attributes"].contains("COLOR_0"));
  EXPECT_EQ(plain.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][0], 0.8);
}

TEST_F(AnimateGltf, NormalsAreUnitSmoothPerMaterialAndSplitAtTheRim) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  const std::vector<double> n = accessor_values(g, g.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]);
  ASSERT_EQ(n.size(), 21u);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_NEAR(std::hypot(n[3 * i], n[3 * i + 1], n[3 * i + 2]), 1.0, 1e-6);
  // The rim copies carry the fracture face's normal (1, 1, 1) / sqrt 3; vertex 1 its exterior one.
  for (std::size_t i = 4; i < 7; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(n[3 * i + std::size_t(k)], 1.0 / std::sqrt(3.0), 1e-6);
  EXPECT_LT(n[3 * 1 + 0], 0.5);
}

TEST_F(AnimateGltf, RigidPiecesMoveByNodeTransformsReproducingEveryFrame) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  const Json& anim = g.json["animations"][0];
  ASSERT_EQ(anim["channels"].size(), 4u);
  EXPECT_EQ(anim["channels"][2]["target"]["node"], 1);
  EXPECT_EQ(anim["channels"][2]["target"]["path"], "translation");
  EXPECT_EQ(anim["channels"][3]["target"]["path"], "rotation");
  for (std::size_t t = 0; t < 3; ++t)
    for (std::size_t p = 0; p < 2; ++p) {
      const std::vector<glm::dvec3> x = positions_at(g, p, 4, t);
      for (std::size_t i = 0; i < 4; ++i) EXPECT_LT(glm::length(x[i] - result.frames[t][4 * p + i]), 1e-6) << p << " " << t;
    }
  const std::vector<double> times = accessor_values(g, anim["samplers"][0]["input"]);
  ASSERT_EQ(times.size(), 3u);
  for (std::size_t t = 0; t < 3; ++t) EXPECT_EQ(times[t], double(float(double(t) / 24.0)));
  EXPECT_EQ(anim["extras"]["frame_count"], 3);
  EXPECT_EQ(g.json["nodes"][1]["translation"].size(), 3u);  // frame 0's pose, for readers without animation
}

TEST_F(AnimateGltf, DeformingPieceUsesSparseMorphTargetsReproducingEveryFrame) {
  GltfSummary s;
  const Glb g = parse_glb(encode_animation_glb(set, stretched, {}, &s));
  EXPECT_EQ(s.rigid_pieces, 1u);
  const Json& prim = g.json["meshes"][1]["primitives"][0];
  ASSERT_EQ(prim["targets"].size(), 2u);
  EXPECT_FALSE(g.json["meshes"][0]["primitives"][0].contains("targets"));
  EXPECT_EQ(g.json["meshes"][1]["extras"]["targetNames"], Json::array({"frame_0001", "frame_0002"}));
  const Json& target = g.json["accessors"][prim["targets"][0]["POSITION"].get<std::size_t>()];
  EXPECT_FALSE(target.contains("bufferView"));
  EXPECT_EQ(target["sparse"]["count"], 3);  // (0, 0, 1), (1, 1, 1) and the rim copy of (0, 0, 1)
  EXPECT_EQ(channel_at(g, 1, "weights", 2), (std::vector<double>{0, 1}));
  for (std::size_t t = 0; t < 3; ++t) {
    const std::vector<glm::dvec3> x = positions_at(g, 1, 4, t);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_LT(glm::length(x[i] - stretched.frames[t][4 + i]), 1e-6);
  }
}

TEST_F(AnimateGltf, EveryPositionAccessorHasItsExactBounds) {
  const Glb g = parse_glb(encode_animation_glb(set, stretched));
  std::size_t checked = 0;
  for (const Json& mesh : g.json["meshes"])
    for (const Json& prim : mesh["primitives"]) {
      std::vector<std::size_t> ids = {prim["attributes"]["POSITION"].get<std::size_t>()};
      for (const Json& t : prim.value("targets", Json::array())) ids.push_back(t["POSITION"]);
      for (std::size_t id : ids) {
        const std::vector<double> v = accessor_values(g, id);
        const Json& a = g.json["accessors"][id];
        ASSERT_TRUE(a.contains("min") && a.contains("max"));
        for (int k = 0; k < 3; ++k) {
          double lo = INFINITY, hi = -INFINITY;
          for (std::size_t i = std::size_t(k); i < v.size(); i += 3) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
          EXPECT_EQ(a["min"][k].get<double>(), lo);
          EXPECT_EQ(a["max"][k].get<double>(), hi);
        }
        ++checked;
      }
    }
  EXPECT_EQ(checked, 8u);  // piece 0: 2 primitives x base; piece 1: 2 x (base + 2 targets)
}

TEST_F(AnimateGltf, SameInputSameBytesAndTheFileHoldsThem) {
  const std::string a = encode_animation_glb(set, result), b = encode_animation_glb(set, three_frames(two_tets()));
  EXPECT_EQ(a, b);
  const auto path = std::filesystem::temp_directory_path() / ("fracref_gltf_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".glb");
  const GltfSummary s = write_animation_glb(set, result, path);
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), a);
  EXPECT_EQ(s.bytes, a.size());
  std::filesystem::remove(path);
}

TEST_F(AnimateGltf, KeptFramesAreEveryKthAndTheLast) {
  EXPECT_EQ(gltf_kept_frames(10, 3), (std::vector<std::size_t>{0, 3, 6, 9}));
  EXPECT_EQ(gltf_kept_frames(11, 3), (std::vector<std::size_t>{0, 3, 6, 9, 10}));
  EXPECT_EQ(gltf_kept_frames(1, 4), (std::vector<std::size_t>{0}));
  EXPECT_EQ(gltf_kept_frames(5, 1).size(), 5u);
}

TEST_F(AnimateGltf, OverTheByteBudgetOnlyEveryKthFrameIsKept) {
  const AnimationResult long_run = three_frames(set, 10, true);
  GltfOptions o;
  // Exactly 4 kept frames: piece 1 deforms (7 vertices), piece 0 is rigid; 44 bytes of vertex
  // data per vertex and 12 per triangle; the weights; 256 bytes of JSON per piece and frame.
  const std::size_t kept = 4, fixed = 2 * (44 * 7 + 12 * 4);
  o.max_bytes = 12 * 7 * kept + 28 * kept + 4 * kept + 4 * kept * (kept - 1) + fixed + 256 * 2 * kept;
  GltfSummary s;
  const Glb g = parse_glb(encode_animation_glb(set, long_run, o, &s));
  EXPECT_EQ(s.frame_step, 3u);
  EXPECT_EQ(s.frames_kept, 4u);  // 0, 3, 6, 9
  EXPECT_FALSE(s.over_budget);
  EXPECT_EQ(g.json["meshes"][1]["primitives"][0]["targets"].size(), 3u);
  EXPECT_EQ(g.json["meshes"][1]["extras"]["targetNames"], Json::array({"frame_0003", "frame_0006", "frame_0009"}));
  EXPECT_EQ(g.json["animations"][0]["extras"]["frame_step"], 3);
  const std::vector<double> times = accessor_values(g, g.json["animations"][0]["samplers"][0]["input"]);
  EXPECT_EQ(times.back(), double(float(9.0 / 24.0)));
  o.max_bytes = 1;  // nothing fits: the first and last frames are kept anyway
  encode_animation_glb(set, long_run, o, &s);
  EXPECT_EQ(s.frames_kept, 2u);
  EXPECT_TRUE(s.over_budget);
}

TEST_F(AnimateGltf, OneFrameHasNoTargetsAndNoAnimation) {
  const Glb g = parse_glb(encode_animation_glb(set, three_frames(set, 1)));
  EXPECT_FALSE(g.json.contains("animations"));
  EXPECT_FALSE(g.json["meshes"][0]["primitives"][0].contains("targets"));
  EXPECT_EQ(g.json["nodes"][0]["rotation"].size(), 4u);
}

TEST_F(AnimateGltf, BadFramesAreRunErrors) {
  AnimationResult r = result;
  r.frames[2].pop_back();
  EXPECT_THROW(encode_animation_glb(set, r), RunError);
  r = result;
  r.frames[1][5].y = NAN;
  EXPECT_THROW(encode_animation_glb(set, r), RunError);
  r.frames.clear();
  EXPECT_THROW(encode_animation_glb(set, r), RunError);
  r = result;
  r.layout.vertices[1] = {1, 2, 3};  // piece 1 uses vertex 4, which the layout does not move
  r.layout.offsets = {0, 4, 7};
  EXPECT_THROW(encode_animation_glb(set, r), RunError);
  r = result;
  r.fps = 0.0;
  EXPECT_THROW(encode_animation_glb(set, r), RunError);
  PieceSet no_faces = set;
  no_faces.pieces[1].triangles.clear();
  no_faces.pieces[1].inside.clear();
  EXPECT_THROW(encode_animation_glb(no_faces, result), RunError);
}

TEST(RigidFit, RecoversARotationAndTranslation) {
  const std::vector<glm::dvec3> rest = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 1, 1}};
  const glm::dquat q = glm::normalize(glm::dquat(0.8, 0.1, -0.5, 0.3));
  const glm::dvec3 t(4, -2, 0.5), pivot(0.5, 0.5, 0.5);
  std::vector<glm::dvec3> moved;
  for (const glm::dvec3& x : rest) moved.push_back(glm::mat3_cast(q) * (x - pivot) + t);
  const RigidPose pose = fit_rigid(rest.data(), moved.data(), rest.size(), pivot);
  EXPECT_NEAR(std::abs(glm::dot(pose.rotation, q)), 1.0, 1e-12);
  EXPECT_LT(glm::length(pose.translation - t), 1e-12);
  EXPECT_GE(pose.rotation.w, 0.0);
}

TEST(PieceSurface, BoxTexcoordDropsTheDominantAxis) {
  EXPECT_EQ(box_texcoord({1, 2, 3}, {0.9, 0.1, 0.1}, {0, 0, 0}, 2.0), glm::dvec2(1.0, 1.5));
  EXPECT_EQ(box_texcoord({1, 2, 3}, {0.1, -0.9, 0.1}, {0, 0, 0}, 2.0), glm::dvec2(1.5, 0.5));
  EXPECT_EQ(box_texcoord({1, 2, 3}, {0.1, 0.1, 0.9}, {0, 0, 0}, 2.0), glm::dvec2(0.5, 1.0));
}

}  // namespace
}  // namespace fracref
