// The strict PLY reader, ASCII and binary little-endian: accepted files with exact counts and
// properties, and every malformed case with the file, line or byte offset and cause.
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "io/mesh_io.hpp"
#include "io/mesh_stats.hpp"
#include "util/error.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

// Little-endian bytes of a binary PLY body, whatever the host.
struct Bytes {
  std::string s;
  template <typename T>
  Bytes& put(T v) {
    using U = std::conditional_t<sizeof(T) == 1, std::uint8_t, std::conditional_t<sizeof(T) == 2, std::uint16_t,
              std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    U u = std::bit_cast<U>(v);
    for (std::size_t i = 0; i < sizeof(T); ++i) s += static_cast<char>((u >> (8 * i)) & 0xff);
    return *this;
  }
  Bytes& tri(std::int32_t a, std::int32_t b, std::int32_t c) { return put<std::uint8_t>(3).put(a).put(b).put(c); }
  Bytes& xyz(double x, double y, double z) { return put(x).put(y).put(z); }
};

class PlyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_io_ply_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& bytes) {
    fs::path p = dir_ / "m.ply";
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  MeshSoup read(const std::string& bytes) { return read_ply(write(bytes)); }

  // Reading fails with a message that starts "<file><where>" ( ":12: " or ": byte 40: ") and
  // contains `cause`.
  ::testing::AssertionResult fails(const std::string& bytes, const std::string& where, const std::string& cause) {
    fs::path p = write(bytes);
    std::string msg = "<no error>";
    try {
      read_ply(p);
    } catch (const InputError& e) {
      msg = e.what();
    }
    std::string start = p.string() + where;
    if (msg.rfind(start, 0) == 0 && msg.find(cause) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message '" << msg << "' lacks '" << start << "' or '" << cause << "'";
  }
  static std::string line(std::size_t n) { return ":" + std::to_string(n) + ": "; }
  static std::string byte(std::size_t n) { return ": byte " + std::to_string(n) + ": "; }

  fs::path dir_;
};

const std::string kAsciiHead =
    "ply\nformat ascii 1.0\ncomment tetra\nelement vertex 4\nproperty double x\nproperty double y\n"
    "property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";  // 10 lines
const std::string kAsciiBody = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";

std::string binary_head(std::size_t vertices, std::size_t faces, const std::string& vertex_type = "double") {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices) + "\nproperty " +
         vertex_type + " x\nproperty " + vertex_type + " y\nproperty " + vertex_type + " z\nelement face " +
         std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

Bytes tetra_body() {
  Bytes b;
  b.xyz(0, 0, 0).xyz(1, 0, 0).xyz(0, 1, 0).xyz(0, 0, 1);
  b.tri(0, 2, 1).tri(0, 1, 3).tri(1, 2, 3).tri(2, 0, 3);
  return b;
}

using Tri = std::array<std::uint32_t, 3>;

}  // namespace

TEST_F(PlyTest, AsciiTetrahedron) {
  MeshSoup s = read(kAsciiHead + kAsciiBody);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.triangles[3], (Tri{2, 0, 3}));
  EXPECT_TRUE(s.vertex_properties.empty());
  EXPECT_TRUE(s.face_properties.empty());
  MeshStats st = mesh_stats(s);
  EXPECT_TRUE(st.closed);
  EXPECT_EQ(st.components, 1u);
}

TEST_F(PlyTest, BinaryTetrahedronMatchesAscii) {
  MeshSoup a = read(kAsciiHead + kAsciiBody);
  MeshSoup b = read(binary_head(4, 4) + tetra_body().s);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST_F(PlyTest, CrlfHeaderAndBlankDataLines) {
  std::string head;
  for (char c : kAsciiHead) head += c == '\n' ? std::string("\r\n") : std::string(1, c);
  std::string body = "0 0 0\r\n1 0 0\r\n\r\n0 1 0\r\n0 0 1\r\n3 0 2 1\r\n3 0 1 3\r\n3 1 2 3\r\n3 2 0 3\r\n\r\n";
  EXPECT_EQ(read(head + body).triangles.size(), 4u);
  Bytes b = tetra_body();
  std::string bhead;
  for (char c : binary_head(4, 4)) bhead += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_EQ(read(bhead + b.s).positions[3], glm::dvec3(0, 0, 1));
}

TEST_F(PlyTest, FloatVerticesOtherIndexTypesAndSizedTypeNames) {
  std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float32 x\nproperty float y\n"
      "property int16 z\nelement face 1\nproperty list uint8 uint32 vertex_index\nend_header\n";
  Bytes b;
  b.put(0.1f).put(2.5f).put<std::int16_t>(-7);
  b.put(1.0f).put(0.0f).put<std::int16_t>(0);
  b.put(0.0f).put(1.0f).put<std::int16_t>(3);
  b.put<std::uint8_t>(3).put<std::uint32_t>(2).put<std::uint32_t>(1).put<std::uint32_t>(0);
  MeshSoup s = read(head + b.s);
  EXPECT_EQ(s.positions[0], glm::dvec3(double(0.1f), 2.5, -7.0));
  EXPECT_EQ(s.triangles[0], (Tri{2, 1, 0}));
}

TEST_F(PlyTest, ExtraPropertiesAreKeptAndFaceValuesRepeatPerTriangle) {
  std::string text =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property float w0\nproperty uchar label\nelement face 2\nproperty int front\n"
      "property list uchar int vertex_indices\nproperty int back\nend_header\n"
      "0 0 0 0.25 1\n1 0 0 0.5 2\n1 1 0 0.75 3\n0 1 0 1e-3 255\n7 4 0 1 2 3 -1\n8 3 0 2 1 9\n";
  MeshSoup s = read(text);
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.polygons_triangulated, 1u);
  ASSERT_EQ(s.vertex_properties.size(), 2u);
  EXPECT_EQ(s.vertex_properties[0].name, "w0");
  EXPECT_EQ(s.vertex_properties[0].type, PropertyType::Float32);
  EXPECT_EQ(s.vertex_properties[0].values, (std::vector<double>{0.25, 0.5, 0.75, 1e-3}));  // kept as written
  EXPECT_EQ(s.vertex_properties[1].type, PropertyType::UInt8);
  EXPECT_EQ(s.vertex_properties[1].values, (std::vector<double>{1, 2, 3, 255}));
  ASSERT_EQ(s.face_properties.size(), 2u);
  EXPECT_EQ(s.face_properties[0].name, "front");
  EXPECT_EQ(s.face_properties[0].values, (std::vector<double>{7, 7, 8}));
  EXPECT_EQ(s.face_properties[1].name, "back");
  EXPECT_EQ(s.face_properties[1].values, (std::vector<double>{-1, -1, 9}));
}

TEST_F(PlyTest, FacesMayComeBeforeVerticesAndFacesMayBeAbsent) {
  MeshSoup s = read("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "element vertex 3\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
                    "3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.positions.size(), 3u);
  MeshSoup cloud = read("ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                        "property double z\nend_header\n1 2 3\n");
  EXPECT_EQ(cloud.positions.size(), 1u);
  EXPECT_TRUE(cloud.triangles.empty());
}

TEST_F(PlyTest, HeaderProblems) {
  const std::string v = "element vertex 0\nproperty float x\nproperty float y\nproperty float z\n";
  EXPECT_TRUE(fails("plyx\n", line(1), "not a PLY file"));
  EXPECT_TRUE(fails("ply\nformat binary_big_endian 1.0\n", line(2),
                    "format binary_big_endian is not supported (only ascii and binary_little_endian)"));
  EXPECT_TRUE(fails("ply\nformat utf8 1.0\n", line(2), "unknown PLY format 'utf8'"));
  EXPECT_TRUE(fails("ply\nformat ascii 2.0\n", line(2), "unsupported PLY version '2.0'"));
  EXPECT_TRUE(fails("ply\nelement vertex 1\n", line(2), "the format line must come before 'element'"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nelement vertex 1\nproperty int64 x\n", line(4), "unknown property type 'int64'"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nelement edge 1\n", line(3), "unsupported element 'edge' (only vertex and face)"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v + "property list uchar float normals\n", line(7),
                    "list property 'normals' is not supported (only the face index list)"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v + "element face 0\nproperty list uchar int vertex_indices\n"
                    "property list uchar float texcoord\n", line(9), "list property 'texcoord' is not supported"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v + "element face 0\nproperty list uchar float vertex_indices\n",
                    line(8), "the face index list needs integer count and item types"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float z\nend_header\n", line(6),
                    "the vertex element has no property 'y'"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v + "element face 0\nproperty int front\nend_header\n", line(9),
                    "the face element has no vertex_indices list property"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v, line(6), "the header has no end_header line"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\n" + v + "property float x\n", line(7), "property 'x' declared twice"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nelement vertex -1\n", line(3), "element count '-1' is negative"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nproperty float x\n", line(3), "property before any element"));
  EXPECT_TRUE(fails("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
                    line(5), "the header declares no vertex element"));
}

TEST_F(PlyTest, AsciiCountsThatDoNotMatchTheData) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n";
  EXPECT_TRUE(fails(kAsciiHead + body, line(17), "file ends after 3 of the 4 face elements announced in the header"));
  EXPECT_TRUE(fails(kAsciiHead + "0 0 0\n", line(11), "file ends after 1 of the 4 vertex elements"));
  EXPECT_TRUE(fails(kAsciiHead + kAsciiBody + "3 0 1 2\n", line(19), "extra data after the last element"));
  EXPECT_TRUE(fails(kAsciiHead + "0 0 0 0\n", line(11), "vertex 0 has 1 values more than the header declares"));
  EXPECT_TRUE(fails(kAsciiHead + "0 0\n", line(11), "vertex 0 has too few values"));
  EXPECT_TRUE(fails(kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 1 2\n", line(15), "face 0 has too few values"));
}

TEST_F(PlyTest, AsciiBadValues) {
  EXPECT_TRUE(fails(kAsciiHead + "0 0 0\nnan 0 0\n", line(12), "vertex 1, property 'x': value 'nan' is not finite"));
  EXPECT_TRUE(fails(kAsciiHead + "0 0 1e999\n", line(11), "property 'z': value '1e999' is out of the range of double"));
  EXPECT_TRUE(fails(kAsciiHead + "0 1,5 0\n", line(11), "comma used as decimal separator"));
  EXPECT_TRUE(fails(kAsciiHead + "0 abc 0\n", line(11), "value 'abc' is not a number"));
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\nproperty double z\n"
      "property uchar label\nproperty float w\nend_header\n";  // 9 lines
  EXPECT_TRUE(fails(head + "0 0 0 300 0\n", line(10), "property 'label': value '300' does not fit uchar"));
  EXPECT_TRUE(fails(head + "0 0 0 -1 0\n", line(10), "value '-1' does not fit uchar"));
  EXPECT_TRUE(fails(head + "0 0 0 1.5 0\n", line(10), "value '1.5' is not an integer"));
  EXPECT_TRUE(fails(head + "0 0 0 1 1e39\n", line(10), "property 'w': value '1e39' overflows float"));
}

TEST_F(PlyTest, BadFaces) {
  const std::string v = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string ok = "3 0 2 1\n3 0 1 3\n3 1 2 3\n";
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "3 2 0 4\n", line(18), "face 3 vertex index 4 is out of range (the header declares 4 vertices)"));
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "3 2 -1 3\n", line(18), "face 3 vertex index -1 is negative"));
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "3 2 2 3\n", line(18), "face 3 repeats vertex 2"));
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "2 2 3\n", line(18), "face 3 has 2 vertices; a face needs at least 3"));
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "3 2 0 x\n", line(18), "value 'x' is not an integer"));
  EXPECT_TRUE(fails(kAsciiHead + v + ok + "3 2 0 3 1\n", line(18), "face 3 has 1 values more"));
}

TEST_F(PlyTest, BinaryTruncatedExtraAndNonFinite) {
  const std::string head = binary_head(4, 4);
  const std::string body = tetra_body().s;
  const std::size_t start = head.size();
  EXPECT_TRUE(fails(head + body.substr(0, body.size() - 2), byte(start + body.size() - 2),
                    "file ends inside face 3 (truncated)"));
  EXPECT_TRUE(fails(head + body.substr(0, 30), byte(start + 30), "file ends inside vertex 1 (truncated)"));
  EXPECT_TRUE(fails(head, byte(start), "file ends inside vertex 0 (truncated)"));
  EXPECT_TRUE(fails(head + body + "xyz", byte(start + body.size()), "3 bytes of extra data after the last element"));
  Bytes nan;
  nan.xyz(0, 0, 0).xyz(1, std::numeric_limits<double>::quiet_NaN(), 0);
  EXPECT_TRUE(fails(head + nan.s, byte(start + 32), "vertex 1, property 'y': value nan is not finite"));
  Bytes inf;
  inf.put(0.0f).put(std::numeric_limits<float>::infinity()).put(0.0f);
  EXPECT_TRUE(fails(binary_head(1, 0, "float") + inf.s, byte(binary_head(1, 0, "float").size() + 4), "is not finite"));
}

TEST_F(PlyTest, BinaryBadFaces) {
  const std::string head = binary_head(4, 1);
  Bytes v;
  v.xyz(0, 0, 0).xyz(1, 0, 0).xyz(0, 1, 0).xyz(0, 0, 1);
  const std::size_t face = head.size() + 96;
  EXPECT_TRUE(fails(head + Bytes(v).tri(0, 1, 4).s, byte(face + 9), "face 0 vertex index 4 is out of range"));
  EXPECT_TRUE(fails(head + Bytes(v).tri(0, -2, 3).s, byte(face + 5), "face 0 vertex index -2 is negative"));
  EXPECT_TRUE(fails(head + Bytes(v).tri(3, 1, 3).s, byte(face + 9), "face 0 repeats vertex 3"));
  EXPECT_TRUE(fails(head + Bytes(v).put<std::uint8_t>(2).put(0).put(1).s, byte(face), "face 0 has 2 vertices"));
}

TEST_F(PlyTest, EmptyAndMissingFiles) {
  fs::path p = write("");
  try {
    read_ply(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ": file is empty");
  }
  EXPECT_THROW(read_ply(dir_ / "nothing.ply"), InputError);
}
