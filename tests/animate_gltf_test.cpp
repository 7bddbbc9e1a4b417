// animation.glb: two tetrahedra sharing a fracture face, three frames in which the second one
// moves rigidly. The GLB is parsed back here, independently of the writer: the container (magic,
// version, length, padded chunks), the JSON (nodes, primitives, accessors and their bounds), the
// morph targets (base + delta reproduces every frame), the animation keys, decimation under a
// byte budget, determinism and the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "animate/gltf_writer.hpp"
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

// The values of a float or uint32 accessor (zeros without a buffer view), bounds-checked.
std::vector<double> accessor_values(const Glb& g, std::size_t index) {
  const Json& a = g.json["accessors"][index];
  const std::size_t width = a["type"] == "VEC3" ? 3 : 1;
  std::vector<double> out(a["count"].get<std::size_t>() * width, 0.0);
  if (!a.contains("bufferView")) return out;
  const Json& view = g.json["bufferViews"][a["bufferView"].get<std::size_t>()];
  const std::size_t offset = view["byteOffset"].get<std::size_t>();
  EXPECT_EQ(view["byteLength"].get<std::size_t>(), out.size() * 4);
  EXPECT_LE(offset + out.size() * 4, g.bin.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t raw = u32_at(g.bin, offset + 4 * i);
    float f;
    std::memcpy(&f, &raw, 4);
    out[i] = a["componentType"] == 5126 ? double(f) : double(raw);
  }
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

// Frame t: piece 0 still, piece 1 turned by 0.3 t radians about z and moved by 0.5 t along x.
AnimationResult three_frames(const PieceSet& set, std::size_t frames = 3) {
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
      x.push_back({c * p.x - s * p.y + 0.5 * double(t), s * p.x + c * p.y, p.z + 0.1});
    }
    r.frames.push_back(x);
  }
  return r;
}

class AnimateGltf : public ::testing::Test {
 protected:
  PieceSet set = two_tets();
  AnimationResult result = three_frames(set);
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
  EXPECT_FALSE(s.over_budget);
}

TEST_F(AnimateGltf, NodesMeshesAndPrimitivesFollowThePieces) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  ASSERT_EQ(g.json["nodes"].size(), 2u);
  EXPECT_EQ(g.json["nodes"][1]["name"], "piece_001");
  EXPECT_EQ(g.json["nodes"][1]["mesh"], 1);
  EXPECT_EQ(g.json["scenes"][0]["nodes"], Json::array({0, 1}));
  EXPECT_EQ(g.json["materials"][0]["name"], "exterior");
  EXPECT_EQ(g.json["materials"][1]["name"], "inside");
  EXPECT_EQ(g.json["materials"][1]["doubleSided"], false);
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prims = g.json["meshes"][p]["primitives"];
    ASSERT_EQ(prims.size(), 2u);
    EXPECT_EQ(prims[0]["material"], 0);
    EXPECT_EQ(prims[1]["material"], 1);
    EXPECT_EQ(prims[0]["attributes"]["POSITION"], prims[1]["attributes"]["POSITION"]);
    EXPECT_EQ(accessor_values(g, prims[0]["attributes"]["POSITION"]).size(), 12u);
    EXPECT_EQ(g.json["accessors"][prims[0]["indices"].get<std::size_t>()]["componentType"], 5125);
    EXPECT_EQ(prims[0]["targets"].size(), 2u);
    EXPECT_EQ(g.json["meshes"][p]["extras"]["targetNames"], Json::array({"frame_0001", "frame_0002"}));
  }
  // Piece 1's faces on its local vertices (1, 2, 3, 4) -> (0, 1, 2, 3): outside first, then inside.
  const Json& prims = g.json["meshes"][1]["primitives"];
  EXPECT_EQ(accessor_values(g, prims[0]["indices"]), (std::vector<double>{0, 1, 3, 1, 2, 3, 2, 0, 3}));
  EXPECT_EQ(accessor_values(g, prims[1]["indices"]), (std::vector<double>{0, 2, 1}));
}

TEST_F(AnimateGltf, EveryPositionAccessorHasItsExactBounds) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  std::size_t checked = 0;
  for (const Json& mesh : g.json["meshes"])
    for (const Json& prim : mesh["primitives"]) {
      std::vector<std::size_t> ids = {prim["attributes"]["POSITION"].get<std::size_t>()};
      for (const Json& t : prim["targets"]) ids.push_back(t["POSITION"]);
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
  EXPECT_EQ(checked, 12u);  // 2 pieces x 2 primitives x (base + 2 targets)
}

TEST_F(AnimateGltf, BasePlusMorphDeltaReproducesEveryFrame) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  for (std::size_t p = 0; p < 2; ++p) {
    const Json& prim = g.json["meshes"][p]["primitives"][0];
    const std::vector<double> base = accessor_values(g, prim["attributes"]["POSITION"]);
    for (std::size_t t = 0; t < 3; ++t) {
      std::vector<double> x = base;
      if (t > 0) {
        const std::vector<double> d = accessor_values(g, prim["targets"][t - 1]["POSITION"]);
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = double(float(x[i]) + float(d[i]));
      }
      for (std::size_t i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[3 * i + std::size_t(k)], result.frames[t][4 * p + i][k], 1e-6);
    }
  }
  // Piece 0 does not move: its targets are all-zero accessors without a buffer view.
  const Json& still = g.json["meshes"][0]["primitives"][0]["targets"][1]["POSITION"];
  EXPECT_FALSE(g.json["accessors"][still.get<std::size_t>()].contains("bufferView"));
}

TEST_F(AnimateGltf, OneWeightsChannelPerNodeWithUnitVectorKeys) {
  const Glb g = parse_glb(encode_animation_glb(set, result));
  ASSERT_EQ(g.json["animations"].size(), 1u);
  const Json& anim = g.json["animations"][0];
  ASSERT_EQ(anim["channels"].size(), 2u);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(anim["channels"][p]["target"]["node"], p);
    EXPECT_EQ(anim["channels"][p]["target"]["path"], "weights");
    EXPECT_EQ(anim["samplers"][anim["channels"][p]["sampler"].get<std::size_t>()]["interpolation"], "LINEAR");
  }
  const Json& sampler = anim["samplers"][0];
  const std::vector<double> times = accessor_values(g, sampler["input"]);
  ASSERT_EQ(times.size(), 3u);
  for (std::size_t t = 0; t < 3; ++t) EXPECT_EQ(times[t], double(float(double(t) / 24.0)));
  const Json& input = g.json["accessors"][sampler["input"].get<std::size_t>()];
  EXPECT_EQ(input["min"][0].get<double>(), times.front());
  EXPECT_EQ(input["max"][0].get<double>(), times.back());
  EXPECT_EQ(accessor_values(g, sampler["output"]), (std::vector<double>{0, 0, 1, 0, 0, 1}));
  EXPECT_EQ(anim["extras"]["frame_count"], 3);
  EXPECT_EQ(anim["extras"]["frame_step"], 1);
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
  const AnimationResult long_run = three_frames(set, 10);
  GltfOptions o;
  o.max_bytes = 12 * 8 * 4 + 4 * 24 + 4 * 4 + 4 * 4 * 3 + 256 * 2 * 4;  // exactly 4 kept frames of 8 vertices, 2 pieces
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

}  // namespace
}  // namespace fracref
