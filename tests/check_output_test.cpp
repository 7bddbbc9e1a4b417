// fracref check: a small valid output folder made by hand (a box cut in two, written with
// write_pieces, and hand-written frames) passes; each way of breaking it is named.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "animate/piece_surface.hpp"
#include "check/check_output.hpp"
#include "geom/shapes.hpp"
#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

namespace fs = std::filesystem;

MeshSoup to_soup(const TriangleSoup& t) {
  MeshSoup soup;
  soup.positions = t.positions;
  soup.triangles = t.triangles;
  soup.polygons = t.triangles.size();
  for (std::uint32_t i = 0; i < t.triangles.size(); ++i) soup.triangle_polygon.push_back(i);
  return soup;
}

// A planar sheet at x = 1 across the box [0, 2] x [0, 1]^2, split 2 x 2.
FractureSurface sheet() {
  std::vector<glm::vec4> positions;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) positions.emplace_back(1.0f, 0.5f * float(i), 0.5f * float(j), 1.0f);
  std::vector<glm::uvec4> faces;
  for (std::uint32_t j = 0; j < 2; ++j)
    for (std::uint32_t i = 0; i < 2; ++i) {
      const std::uint32_t a = j * 3 + i;
      faces.emplace_back(a, a + 1, a + 4, 0);
      faces.emplace_back(a, a + 4, a + 3, 0);
    }
  return make_fracture_surface(positions, faces, std::vector<glm::ivec2>(faces.size(), glm::ivec2(1, 0)), 2);
}

// Every piece in one OBJ per frame, moved apart by t * 0.1 along x per piece.
std::string frame_text(const PieceSet& set, std::size_t t) {
  std::string out = "mtllib frames.mtl\n";
  std::uint32_t base = 0;
  for (std::size_t p = 0; p < set.pieces.size(); ++p) {
    const auto& piece = set.pieces[p];
    std::vector<std::uint32_t> used;
    for (const auto& tri : piece.triangles) used.insert(used.end(), tri.begin(), tri.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    char name[32];
    std::snprintf(name, sizeof name, "o piece_%03zu\n", p);
    out += name;
    for (std::uint32_t v : used) {
      const glm::dvec3 x = set.positions[v] + glm::dvec3(0.1 * double(t) * double(p), 0, 0);
      out += "v " + std::to_string(x.x) + " " + std::to_string(x.y) + " " + std::to_string(x.z) + "\n";
    }
    for (std::uint8_t group : {0, 1}) {
      out += group ? "usemtl inside\n" : "usemtl outside\n";
      for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
        if (piece.inside[f] != group) continue;
        out += "f";
        for (std::uint32_t v : piece.triangles[f]) {
          const auto local = std::lower_bound(used.begin(), used.end(), v) - used.begin();
          out += ' ';
          out += std::to_string(base + 1 + std::uint32_t(local));
        }
        out += "\n";
      }
    }
    base += std::uint32_t(used.size());
  }
  return out;
}

// animation.glb written by hand, independently of fracref's writer: per piece a mesh with an
// "exterior" and an "inside" primitive on the piece file's vertex order followed by a copy of each
// rim vertex (which the inside faces use), with NORMAL, TEXCOORD_0 and _MATERIAL_POSITION;
// frames 1.. as morph targets (piece p moved by 0.1 t p along x, as frame_text), one weights
// channel per node.
struct HandGlb {
  nlohmann::ordered_json json;
  std::string bin;

  std::size_t add(const std::string& data, int component, std::size_t count, const char* type, nlohmann::ordered_json bounds) {
    json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", data.size()}});
    bin += data;
    nlohmann::ordered_json a = {{"bufferView", json["bufferViews"].size() - 1}, {"componentType", component}, {"count", count}, {"type", type}};
    if (!bounds.is_null()) a["min"] = bounds[0], a["max"] = bounds[1];
    json["accessors"].push_back(a);
    return json["accessors"].size() - 1;
  }
  template <class T>
  static std::string bytes(const std::vector<T>& v) {  // the test host is little-endian, as GLB
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::size_t add_vec3(const std::vector<float>& xyz) {
    nlohmann::ordered_json lo = {xyz[0], xyz[1], xyz[2]}, hi = lo;
    for (std::size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3].get<float>(), xyz[i]), hi[i % 3] = std::max(hi[i % 3].get<float>(), xyz[i]);
    return add(bytes(xyz), 5126, xyz.size() / 3, "VEC3", {lo, hi});
  }
  std::size_t add_floats(const std::vector<float>& v, const char* type) {
    return add(bytes(v), 5126, v.size() / (type[3] == '2' ? 2 : 3), type, nullptr);
  }
  void add_piece(const PieceSet& set, std::size_t p, std::size_t frames, double extra) {
    const auto& piece = set.pieces[p];
    std::vector<std::uint32_t> used;
    for (const auto& tri : piece.triangles) used.insert(used.end(), tri.begin(), tri.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    auto local = [&](std::uint32_t v) { return std::uint32_t(std::lower_bound(used.begin(), used.end(), v) - used.begin()); };
    std::vector<int> uses(used.size(), 0);
    for (std::size_t f = 0; f < piece.triangles.size(); ++f)
      for (std::uint32_t v : piece.triangles[f]) uses[local(v)] |= piece.inside[f] ? 2 : 1;
    std::vector<std::uint32_t> vertex, copy(used.size(), UINT32_MAX);  // per mesh vertex, its piece vertex; rim copies after
    for (std::uint32_t i = 0; i < used.size(); ++i) vertex.push_back(i);
    for (std::uint32_t i = 0; i < used.size(); ++i)
      if (uses[i] == 3) copy[i] = std::uint32_t(vertex.size()), vertex.push_back(i);
    std::vector<float> xyz, normals, uv(2 * vertex.size(), 0.0f);
    for (std::uint32_t i : vertex) {
      const glm::dvec3 x = set.positions[used[i]];
      xyz.insert(xyz.end(), {float(x.x), float(x.y), float(x.z)});
      normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
    }
    const std::size_t position = add_vec3(xyz), normal = add_floats(normals, "VEC3"), material = add_floats(xyz, "VEC3"),
                      texcoord = add_floats(uv, "VEC2");
    nlohmann::ordered_json targets = nlohmann::ordered_json::array();
    for (std::size_t t = 1; t < frames; ++t) {
      std::vector<float> d(xyz.size(), 0.0f);
      for (std::size_t i = 0; i < d.size(); i += 3) d[i] = float((0.1 + extra) * double(t) * double(p));
      targets.push_back({{"POSITION", add_vec3(d)}});
    }
    nlohmann::ordered_json prims = nlohmann::ordered_json::array();
    for (std::uint8_t group : {0, 1}) {
      std::vector<std::uint32_t> idx;
      for (std::size_t f = 0; f < piece.triangles.size(); ++f)
        if (piece.inside[f] == group)
          for (std::uint32_t v : piece.triangles[f]) idx.push_back(group && copy[local(v)] != UINT32_MAX ? copy[local(v)] : local(v));
      const std::size_t indices = add(bytes(idx), 5125, idx.size(), "SCALAR", nullptr);
      const nlohmann::ordered_json attributes = {
          {"POSITION", position}, {"NORMAL", normal}, {"TEXCOORD_0", texcoord}, {"_MATERIAL_POSITION", material}};
      prims.push_back({{"attributes", attributes}, {"indices", indices}, {"material", group}, {"targets", targets}});
    }
    char name[32];
    std::snprintf(name, sizeof name, "piece_%03zu", p);
    json["meshes"].push_back({{"name", name}, {"primitives", prims}});
    json["nodes"].push_back({{"name", name}, {"mesh", p}});
  }
  HandGlb(const PieceSet& set, std::size_t frames, double extra = 0.0) {
    json["asset"] = {{"version", "2.0"}, {"generator", "hand"}};
    json["materials"] = {{{"name", "exterior"}}, {{"name", "inside"}}};
    for (std::size_t p = 0; p < set.pieces.size(); ++p) add_piece(set, p, frames, extra);
    std::vector<float> times, weights;
    for (std::size_t t = 0; t < frames; ++t) {
      times.push_back(float(double(t) / 24.0));
      for (std::size_t k = 1; k < frames; ++k) weights.push_back(k == t ? 1.0f : 0.0f);
    }
    const std::size_t input = add(bytes(times), 5126, times.size(), "SCALAR", {{times.front()}, {times.back()}});
    const std::size_t output = add(bytes(weights), 5126, weights.size(), "SCALAR", nullptr);
    nlohmann::ordered_json anim = {{"channels", nlohmann::ordered_json::array()}, {"samplers", {{{"input", input}, {"output", output}}}}};
    for (std::size_t p = 0; p < set.pieces.size(); ++p) anim["channels"].push_back({{"sampler", 0}, {"target", {{"node", p}, {"path", "weights"}}}});
    json["animations"] = {anim};
    json["buffers"] = {{{"byteLength", bin.size()}}};
  }
  std::string pack(std::string text = "") const {
    if (text.empty()) text = json.dump();
    text.append((4 - text.size() % 4) % 4, ' ');
    std::vector<std::uint32_t> head = {0x46546C67, 2, std::uint32_t(12 + 8 + text.size() + 8 + bin.size()), std::uint32_t(text.size()), 0x4E4F534A};
    return bytes(head) + text + bytes(std::vector<std::uint32_t>{std::uint32_t(bin.size()), 0x004E4942}) + bin;
  }
};

class CheckOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_check_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "frames");
    const MeshSoup exterior = to_soup(make_box({0, 0, 0}, {2, 1, 1}, 2));
    set_ = build_pieces(sheet(), exterior);
    write_pieces(set_, dir_);
    write_piece_objs(set_, dir_);
    write_mesh(dir_ / "exterior.ply", exterior);
    nlohmann::ordered_json report = {{"version", "test"}, {"pieces", 2}, {"frames", 3}};
    for (std::size_t p = 0; p < 2; ++p) report["piece_meshes"].push_back({{"piece", p}, {"triangles", set_.pieces[p].triangles.size()}});
    write("report.json", report.dump(2));
    for (std::size_t t = 0; t < 3; ++t) write("frames/frame_000" + std::to_string(t) + ".obj", frame_text(set_, t));
    write("animation.glb", HandGlb(set_, 3).pack());
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name, std::ios::binary) << text; }
  fs::path piece_ply(int p) const { return dir_ / "pieces" / ("piece_00" + std::to_string(p) + ".ply"); }

  // The failure lines of a check that must fail, with the named check failed.
  std::string failures_of(const std::string& check) {
    const CheckReport r = check_output(dir_);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.exit_code(), 1);
    std::string all;
    for (const std::string& f : r.failures) all += f + "\n";
    bool found = false;
    for (const CheckResult& c : r.checks)
      if (c.name == check) {
        found = true;
        EXPECT_EQ(c.status, CheckStatus::kFailed) << all;
      }
    EXPECT_TRUE(found) << check;
    return all;
  }

  fs::path dir_;
  PieceSet set_;
};

TEST_F(CheckOutput, ValidFolderPasses) {
  const CheckReport r = check_output(dir_);
  for (const std::string& f : r.failures) ADD_FAILURE() << f;
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.exit_code(), 0);
  EXPECT_EQ(r.pieces, 2u);
  EXPECT_EQ(r.frames, 3u);
  ASSERT_EQ(r.checks.size(), 8u);
  for (const CheckResult& c : r.checks) EXPECT_EQ(c.status, CheckStatus::kPassed) << c.name << ": " << c.detail;
  const auto j = check_report_json(r);
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["checks"][5]["name"], "frames");
  EXPECT_EQ(j["checks"][5]["status"], "passed");
  EXPECT_EQ(j["checks"][6]["name"], "glb");
  EXPECT_EQ(j["checks"][6]["detail"], "2 nodes (0 moved by node transforms, 2 by 2 morph targets each), " +
                                          std::to_string(fs::file_size(dir_ / "animation.glb")) + " bytes");
  EXPECT_EQ(j["checks"][7]["name"], "glb_frames");
  EXPECT_EQ(j["checks"][7]["status"], "passed");
}

TEST_F(CheckOutput, ObjOnlyPiecesAreReadWithTheirMaterials) {
  fs::remove(piece_ply(0));
  fs::remove(piece_ply(1));
  const CheckReport r = check_output(dir_);
  for (const std::string& f : r.failures) ADD_FAILURE() << f;
  EXPECT_TRUE(r.ok());
}

TEST_F(CheckOutput, DeletedTriangleIsNotClosed) {
  MeshSoup m = read_ply(piece_ply(1));
  m.triangles.pop_back();
  m.triangle_polygon.pop_back();
  m.face_properties[0].values.pop_back();
  write_mesh(piece_ply(1), m);
  const std::string all = failures_of("piece_meshes");
  EXPECT_NE(all.find("pieces/piece_001.ply: not closed (3 edges with one face"), std::string::npos) << all;
  EXPECT_NE(all.find("pieces/piece_001.ply: " + std::to_string(m.triangles.size()) + " triangles, report.json says"),
            std::string::npos) << all;
  EXPECT_NE(all.find("frames/frame_0000.obj: piece_001 has"), std::string::npos) << all;
  EXPECT_EQ(all.find("piece_000.ply"), std::string::npos) << all;
}

TEST_F(CheckOutput, FlippedTriangleIsInconsistentlyOriented) {
  MeshSoup m = read_ply(piece_ply(0));
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  write_mesh(piece_ply(0), m);
  const std::string all = failures_of("piece_meshes");
  EXPECT_NE(all.find("pieces/piece_000.ply: inconsistently oriented (3 edges used twice in one direction"), std::string::npos) << all;
  EXPECT_NE(all.find("frames/frame_0000.obj: piece_000 has triangle"), std::string::npos) << all;
}

TEST_F(CheckOutput, SharedVertexMovedByOneUlpIsNamed) {
  MeshSoup m = read_ply(piece_ply(1));
  std::uint32_t v = UINT32_MAX;  // the fracture vertex in the middle of the sheet
  for (std::uint32_t i = 0; i < m.positions.size(); ++i)
    if (m.positions[i] == glm::dvec3(1.0, 0.5, 0.5)) v = i;
  ASSERT_NE(v, UINT32_MAX);
  m.positions[v].x = std::nextafter(m.positions[v].x, 10.0);
  write_mesh(piece_ply(1), m);
  const CheckReport r = check_output(dir_);
  std::string all;
  for (const std::string& f : r.failures) all += f + "\n";
  for (const CheckResult& c : r.checks)
    EXPECT_EQ(c.status, c.name == "shared_vertices" ? CheckStatus::kFailed : CheckStatus::kPassed) << c.name << "\n" << all;
  EXPECT_NE(all.find("pieces/piece_001.ply: 1 of "), std::string::npos) << all;
  EXPECT_NE(all.find("fracture vertices are not shared bit for bit with another piece, e.g. vertex " + std::to_string(v)),
            std::string::npos) << all;
  EXPECT_NE(all.find("pieces/piece_000.ply: 1 of "), std::string::npos) << all;
}

TEST_F(CheckOutput, DroppedAndExtraFramesAreNamed) {
  fs::remove(dir_ / "frames" / "frame_0001.obj");
  write("frames/frame_0007.obj", frame_text(set_, 0));
  const std::string all = failures_of("frames");
  EXPECT_NE(all.find("frames: 1 of report.json's 3 frames missing: frame_0001.obj"), std::string::npos) << all;
  EXPECT_NE(all.find("frames: 1 frame files beyond report.json's 3: frame_0007.obj"), std::string::npos) << all;
}

// frames/ as topology.obj and positions.bin (scenes/OUTPUTS.md), written here by hand.
std::string positions_bin(const PieceSet& set, std::size_t frames, std::size_t skip_last_floats = 0) {
  std::vector<std::vector<glm::dvec3>> per_frame(frames);  // as frame_text: piece p moved by 0.1 t p along x
  std::vector<std::uint32_t> offsets = {0};
  for (std::size_t p = 0; p < set.pieces.size(); ++p) {
    std::vector<std::uint32_t> used;
    for (const auto& tri : set.pieces[p].triangles) used.insert(used.end(), tri.begin(), tri.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    offsets.push_back(offsets.back() + std::uint32_t(used.size()));
    for (std::size_t t = 0; t < frames; ++t)
      for (std::uint32_t v : used) per_frame[t].push_back(set.positions[v] + glm::dvec3(0.1 * double(t) * double(p), 0, 0));
  }
  std::string out = "FRFRAMES";
  auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  u32(1), u32(std::uint32_t(frames)), u32(std::uint32_t(set.pieces.size())), u32(offsets.back());
  const double fps = 24.0;
  out.append(reinterpret_cast<const char*>(&fps), 8);
  for (std::uint32_t o : offsets) u32(o);
  for (const auto& x : per_frame)
    for (const glm::dvec3& p : x)
      for (int k = 0; k < 3; ++k) {
        const float f = float(p[k]);
        out.append(reinterpret_cast<const char*>(&f), 4);
      }
  return out.substr(0, out.size() - 4 * skip_last_floats);
}

TEST_F(CheckOutput, BinaryFramesAreReadAndMatchTheGlb) {
  for (std::size_t t = 0; t < 3; ++t) fs::remove(dir_ / "frames" / ("frame_000" + std::to_string(t) + ".obj"));
  write("frames/topology.obj", frame_text(set_, 0));
  write("frames/positions.bin", positions_bin(set_, 3));
  CheckReport r = check_output(dir_);
  for (const std::string& f : r.failures) ADD_FAILURE() << f;
  ASSERT_EQ(r.checks.size(), 8u);
  EXPECT_EQ(r.checks[5].detail, "topology.obj and 3 frames of positions.bin read");
  EXPECT_EQ(r.checks[7].status, CheckStatus::kPassed) << r.checks[7].detail;
  write("frames/positions.bin", positions_bin(set_, 3, 3));
  EXPECT_NE(failures_of("frames").find("frames/positions.bin: "), std::string::npos);
  write("frames/positions.bin", positions_bin(set_, 3));
  write("animation.glb", HandGlb(set_, 3, 0.5).pack());  // moves piece 1 half again as far
  EXPECT_NE(failures_of("glb_frames").find("animation.glb: pieces/piece_001.ply vertex "), std::string::npos);
}

TEST_F(CheckOutput, FrameWithoutAPieceOrWithWrongVertexCountIsNamed) {
  std::string text = frame_text(set_, 2);
  write("frames/frame_0002.obj", text.substr(0, text.find("o piece_001")));
  std::string extra = frame_text(set_, 1) + "v 0 0 0\n";
  write("frames/frame_0001.obj", extra);
  const std::string all = failures_of("frames");
  EXPECT_NE(all.find("frames/frame_0002.obj: piece_001 missing"), std::string::npos) << all;
  EXPECT_NE(all.find("frames/frame_0001.obj: "), std::string::npos) << all;
  EXPECT_NE(all.find(" vertices, the pieces use "), std::string::npos) << all;
}

TEST_F(CheckOutput, MissingPieceAndStrayPieceFiles) {
  fs::remove(piece_ply(1));
  fs::remove(dir_ / "pieces" / "piece_001.obj");
  fs::copy_file(piece_ply(0), dir_ / "pieces" / "piece_002.ply");
  const std::string all = failures_of("piece_files");
  EXPECT_NE(all.find("pieces/piece_001.ply: missing"), std::string::npos) << all;
  EXPECT_NE(all.find("pieces/piece_002.ply: not one of the report's 2 pieces"), std::string::npos) << all;
  EXPECT_NE(all.find("exterior.ply: "), std::string::npos) << all;  // the partition no longer holds
}

TEST_F(CheckOutput, MissingExteriorFailsThePartition) {
  fs::remove(dir_ / "exterior.ply");
  const std::string all = failures_of("partition");
  EXPECT_EQ(all, "exterior.ply: missing\n");
}

TEST_F(CheckOutput, WithoutFramesOrPiecesTheChecksAreSkipped) {
  fs::remove_all(dir_ / "frames");
  fs::remove(dir_ / "animation.glb");
  CheckReport r = check_output(dir_);
  EXPECT_TRUE(r.ok());
  ASSERT_EQ(r.checks.size(), 8u);
  EXPECT_EQ(r.checks[5].name, "frames");
  EXPECT_EQ(r.checks[5].status, CheckStatus::kSkipped);
  EXPECT_EQ(r.checks[6].name, "glb");
  EXPECT_EQ(r.checks[6].status, CheckStatus::kSkipped);
  fs::remove_all(dir_ / "pieces");
  write("report.json", R"({"pieces": 2, "frames": 3})");
  r = check_output(dir_);
  EXPECT_TRUE(r.ok());
  ASSERT_EQ(r.checks.size(), 8u);
  for (std::size_t i = 1; i < 8; ++i) EXPECT_EQ(r.checks[i].status, CheckStatus::kSkipped);
}

TEST_F(CheckOutput, TruncatedOrCorruptGlbIsNamed) {
  const std::string good = HandGlb(set_, 3).pack();
  write("animation.glb", good.substr(0, good.size() / 2));
  EXPECT_EQ(failures_of("glb"), "animation.glb: header length " + std::to_string(good.size()) + ", the file has " +
                                    std::to_string(good.size() / 2) + " bytes\n");
  write("animation.glb", good.substr(0, 10));
  EXPECT_EQ(failures_of("glb"), "animation.glb: 10 bytes, shorter than a GLB header and chunk header\n");
  std::string bad = good;
  bad[0] = 'X';
  write("animation.glb", bad);
  EXPECT_EQ(failures_of("glb"), "animation.glb: magic 0x46546C58, expected 0x46546C67 ('glTF')\n");
  bad = good;
  bad[16] = 'B';  // the JSON chunk's type
  write("animation.glb", bad);
  EXPECT_NE(failures_of("glb").find("animation.glb: chunk 0 has type 0x4E4F5342, expected 0x4E4F534A"), std::string::npos);
  bad = good;
  bad[20] = '[';  // the JSON text
  write("animation.glb", bad);
  EXPECT_EQ(failures_of("glb"), "animation.glb: JSON chunk:1:9: syntax error while parsing array - unexpected ':'; expected ']'\n");
}

TEST_F(CheckOutput, GlbJsonThatDoesNotFitTheBinChunkOrThePiecesIsNamed) {
  HandGlb g(set_, 3);
  g.json["accessors"][0]["count"] = g.json["accessors"][0]["count"].get<std::size_t>() + 1;
  write("animation.glb", g.pack());
  EXPECT_NE(failures_of("glb").find("animation.glb: accessors[0]: "), std::string::npos);
  g = HandGlb(set_, 3);
  g.json["bufferViews"][1]["byteLength"] = g.bin.size();
  write("animation.glb", g.pack());
  EXPECT_NE(failures_of("glb").find("animation.glb: bufferViews[1]: bytes ["), std::string::npos);
  g = HandGlb(set_, 3);
  g.json["nodes"].erase(1);
  write("animation.glb", g.pack());
  EXPECT_EQ(failures_of("glb"), "animation.glb: 1 nodes, report.json has 2 pieces\n");
  g = HandGlb(set_, 3);
  g.json["meshes"][1]["primitives"][1]["targets"].erase(1);
  write("animation.glb", g.pack());
  EXPECT_EQ(failures_of("glb"), "animation.glb: meshes[1].primitives[1]: 1 morph targets, expected 2\n");
  g = HandGlb(set_, 3);
  g.json["meshes"][0]["primitives"][0]["material"] = 1;  // outside faces under the inside material
  write("animation.glb", g.pack());
  EXPECT_NE(failures_of("glb").find("triangles differ from the inside faces of pieces/piece_000.ply"), std::string::npos);
  g = HandGlb(set_, 3);
  g.json["accessors"][0].erase("min");
  write("animation.glb", g.pack());
  EXPECT_NE(failures_of("glb").find("POSITION accessor without min and max"), std::string::npos);
  write("animation.glb", HandGlb(set_, 2).pack());  // report.json has 3 frames
  EXPECT_NE(failures_of("glb").find("morph targets, expected 2"), std::string::npos);
  write("animation.glb", g.pack(R"({"asset": {"version": "2.0"}, "asset": {}})"));
  EXPECT_EQ(failures_of("glb"), "animation.glb: JSON chunk: key 'asset': duplicate key (a key may appear only once per object)\n");
}

TEST_F(CheckOutput, FractureFaceColoursAreOnePerVertexAndInTheUnitRange) {
  for (const float c : {0.5f, 1.5f}) {
    HandGlb g(set_, 3);
    const std::size_t position = g.json["meshes"][0]["primitives"][1]["attributes"]["POSITION"];
    const std::size_t vertices = g.json["accessors"][position]["count"];
    const std::size_t colour = g.add_floats(std::vector<float>(3 * vertices, c), "VEC3");
    g.json["meshes"][0]["primitives"][1]["attributes"]["COLOR_0"] = colour;
    g.json["buffers"][0]["byteLength"] = g.bin.size();
    write("animation.glb", g.pack());
    if (c <= 1.0f) {
      const CheckReport r = check_output(dir_);
      for (const std::string& f : r.failures) ADD_FAILURE() << f;
    } else {
      EXPECT_NE(failures_of("glb").find("COLOR_0: a colour component 1.5"), std::string::npos);
    }
  }
}

TEST_F(CheckOutput, NotAFracrefOutputIsAnInputError) {
  auto message = [&] {
    try {
      check_output(dir_);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  write("report.json", "{\"pieces\": 2,");
  EXPECT_NE(message().find("report.json: byte "), std::string::npos) << message();
  write("report.json", R"({"pieces": 2})");
  EXPECT_NE(message().find("report.json: key 'frames' missing"), std::string::npos) << message();
  write("report.json", R"({"pieces": -1, "frames": 0})");
  EXPECT_NE(message().find("key 'pieces' is not a non-negative integer"), std::string::npos) << message();
  fs::remove(dir_ / "report.json");
  EXPECT_NE(message().find("report.json: missing or unreadable"), std::string::npos) << message();
  EXPECT_THROW(check_output(dir_ / "nowhere"), InputError);
  write("report.json", R"({"pieces": 2, "frames": 3})");
  write("frames/frame_0001.obj", "v 0 0 nan\n");
  EXPECT_NE(message().find("frame_0001.obj:1:"), std::string::npos) << message();
}

}  // namespace
}  // namespace fracref
