// The strict OBJ reader: accepted files with exact counts, and every malformed case with the
// file, line and cause in its message.
#include <unistd.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "io/mesh_io.hpp"
#include "io/mesh_stats.hpp"
#include "util/error.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

class ObjTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_io_obj_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& text, const std::string& name = "m.obj") {
    fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  MeshSoup read(const std::string& text) { return read_obj(write(text)); }

  // The message of the InputError that reading `text` raises, or "<no error>".
  std::string error(const std::string& text) {
    fs::path p = write(text);
    try {
      read_obj(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "<no error>";
  }

  // Reading `text` fails at `line` with a message containing `cause`.
  ::testing::AssertionResult fails_at(const std::string& text, std::size_t line, const std::string& cause) {
    std::string msg = error(text);
    std::string where = (dir_ / "m.obj").string() + ":" + std::to_string(line) + ": ";
    if (msg.rfind(where, 0) == 0 && msg.find(cause) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message '" << msg << "' lacks '" << where << "' or '" << cause << "'";
  }

  fs::path dir_;
};

const char* kTetra =
    "# a closed tetrahedron\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
    "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

using Tri = std::array<std::uint32_t, 3>;

}  // namespace

TEST_F(ObjTest, TetrahedronIsReadExactly) {
  MeshSoup s = read(kTetra);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.triangles[0], (Tri{0, 2, 1}));
  EXPECT_EQ(s.triangles[3], (Tri{2, 0, 3}));
  EXPECT_EQ(s.positions[3], glm::dvec3(0, 0, 1));
  EXPECT_EQ(s.polygons, 4u);
  EXPECT_EQ(s.polygons_triangulated, 0u);
  EXPECT_EQ(s.triangle_polygon, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_TRUE(s.groups.empty());
  EXPECT_TRUE(s.triangle_group.empty());
  MeshStats st = mesh_stats(s);
  EXPECT_TRUE(st.closed);
  EXPECT_EQ(st.components, 1u);
}

TEST_F(ObjTest, QuadAndPentagonAreFanTriangulatedAndCounted) {
  MeshSoup s = read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4\nf 1 2 3\nf 1 2 3 4 5\n");
  ASSERT_EQ(s.triangles.size(), 6u);
  EXPECT_EQ(s.polygons, 3u);
  EXPECT_EQ(s.polygons_triangulated, 2u);
  EXPECT_EQ(s.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(s.triangles[1], (Tri{0, 2, 3}));
  EXPECT_EQ(s.triangles[5], (Tri{0, 3, 4}));
  EXPECT_EQ(s.triangle_polygon, (std::vector<std::uint32_t>{0, 0, 1, 2, 2, 2}));
  EXPECT_EQ(mesh_stats(s).polygons_triangulated, 2u);
}

TEST_F(ObjTest, CrlfReadsLikeLf) {
  std::string crlf;
  for (char c : std::string(kTetra)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  MeshSoup a = read(kTetra), b = read(crlf);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_TRUE(fails_at("v 0 0 0\r\nv 1 0 0\r\nv nan 0 0\r\n", 3, "coordinate 'nan' is not finite"));
}

TEST_F(ObjTest, LeadingUtf8ByteOrderMarkIsSkipped) {
  EXPECT_EQ(read(std::string("\xEF\xBB\xBF") + kTetra).triangles.size(), 4u);
  EXPECT_TRUE(fails_at("v 0 0 0\n\xEF\xBB\xBFv 1 0 0\n", 2, "unknown OBJ statement"));  // only at the start
}

TEST_F(ObjTest, FacesBeforeTheirVerticesAreResolvedAfterTheFile) {
  MeshSoup s = read("f 1 2 3\nf 3 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n");
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.triangles[1], (Tri{2, 1, 3}));
  EXPECT_EQ(s.positions.size(), 4u);
}

TEST_F(ObjTest, NegativeIndicesAreRelativeToVerticesSoFar) {
  MeshSoup s = read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -1 -2 -3\n");
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(s.triangles[1], (Tri{3, 2, 1}));
  // -4 with four vertices defined is vertex 1, which the face already names.
  EXPECT_TRUE(fails_at("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 -4 -1\n", 5, "face repeats vertex 1"));
}

TEST_F(ObjTest, TextureAndNormalReferenceFormsAreAccepted) {
  MeshSoup s = read(
      "mtllib a b.mtl\nusemtl stone\ns 1\ns off\n"
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0 0\nvt 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 2//1\nf 1/1 2/2 3/3\nf 1/-3/-1 2/-2/1 3/-1/-1\n");
  EXPECT_EQ(s.triangles.size(), 4u);
}

TEST_F(ObjTest, CommentsBlankLinesWeightOnePlusSignAndUnusedVertices) {
  MeshSoup s = read(
      "# header\n\n   \t\nv 0 0 0 1   # w = 1 is fine\nv +1 0 0\nv 0 1.0e0 0\nv 7 7 7\n  f 1 2 3  # trailing comment\n");
  ASSERT_EQ(s.positions.size(), 4u);
  EXPECT_EQ(s.positions[1].x, 1.0);
  EXPECT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(mesh_stats(s).components, 1u);  // the unused vertex 4 is no component
}

TEST_F(ObjTest, CoordinatesAreParsedExactlyInDouble) {
  MeshSoup s = read("v 0.1 0.30000000000000004 -1.7976931348623157e308\nv 4.9406564584124654e-324 -0 1e-300\n");
  EXPECT_EQ(std::bit_cast<std::uint64_t>(s.positions[0].x), std::bit_cast<std::uint64_t>(0.1));
  EXPECT_EQ(s.positions[0].y, 0.1 + 0.2);
  EXPECT_EQ(s.positions[0].z, -1.7976931348623157e308);
  EXPECT_EQ(s.positions[1].x, 4.9406564584124654e-324);
  EXPECT_TRUE(std::signbit(s.positions[1].y));
}

TEST_F(ObjTest, NonManifoldAndInconsistentWindingAreKeptAsWritten) {
  // A fin: three triangles on edge 1-2, the third wound against the first.
  MeshSoup s = read("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 2 5\n");
  MeshStats st = mesh_stats(s);
  EXPECT_EQ(st.vertices, 5u);
  EXPECT_EQ(st.faces, 3u);
  EXPECT_EQ(st.non_manifold_edges, 1u);
  EXPECT_EQ(st.boundary_edges, 6u);
}

TEST_F(ObjTest, GroupsInOrderOfFirstUse) {
  MeshSoup s = read(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "f 1 2 3\no  big piece \nf 2 4 3\ng small\nf 1 2 4 3\ng big piece\nf 3 2 1\ng\nf 1 3 2\n");
  ASSERT_EQ(s.groups, (std::vector<std::string>{"default", "big piece", "small"}));
  EXPECT_EQ(s.triangle_group, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 0}));
  // A group declared but never used by a face is not listed.
  MeshSoup t = read("v 0 0 0\nv 1 0 0\nv 0 1 0\ng a\ng b\nf 1 2 3\n");
  EXPECT_EQ(t.groups, (std::vector<std::string>{"b"}));
  EXPECT_EQ(t.triangle_group, (std::vector<std::uint32_t>{0}));
}

TEST_F(ObjTest, BadCoordinates) {
  EXPECT_TRUE(fails_at("v 0 0 0\nv nan 0 0\n", 2, "coordinate 'nan' is not finite"));
  EXPECT_TRUE(fails_at("v 0 inf 0\n", 1, "coordinate 'inf' is not finite"));
  EXPECT_TRUE(fails_at("v 0 0 -infinity\n", 1, "is not finite"));
  EXPECT_TRUE(fails_at("v 1e999 0 0\n", 1, "coordinate '1e999' is out of the range of double (overflow"));
  EXPECT_TRUE(fails_at("v 1 2\n", 1, "vertex needs 3 coordinates (or 4 with w = 1), got 2"));
  EXPECT_TRUE(fails_at("v 1 2 3 4 5\n", 1, "got 5"));
  EXPECT_TRUE(fails_at("v 1 2 3 0.5\n", 1, "vertex weight w = 0.5 is not supported"));
  EXPECT_TRUE(fails_at("v x 2 3\n", 1, "coordinate 'x' is not a number"));
  EXPECT_TRUE(fails_at("v 1,5 2 3\n", 1, "coordinate '1,5' is not a number (comma used as decimal separator?)"));
  EXPECT_TRUE(fails_at("v 1.5x 2 3\n", 1, "coordinate '1.5x' is not a number (trailing 'x')"));
  EXPECT_TRUE(fails_at("v 0x10 2 3\n", 1, "is not a number (trailing 'x10')"));
  EXPECT_TRUE(fails_at("v ++1 2 3\n", 1, "coordinate '++1' is not a number"));
  EXPECT_TRUE(fails_at("vt 0.5 nan\n", 1, "texture coordinate 'nan' is not finite"));
  EXPECT_TRUE(fails_at("vt\n", 1, "texture coordinate needs 1 to 3 values, got 0"));
  EXPECT_TRUE(fails_at("vn 0 1\n", 1, "normal needs 3 values, got 2"));
}

TEST_F(ObjTest, BadFaceIndices) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_TRUE(fails_at(v3 + "f 0 1 2\n", 4, "vertex index 0 is invalid (OBJ indices start at 1)"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 3\nf 1 2 9\nf 1 2 3\n", 5, "vertex index 9 is out of range (the file has 3)"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 x\n", 4, "vertex index 'x' is not an integer"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 3.0\n", 4, "vertex index '3.0' is not an integer"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 99999999999999999999\n", 4, "is out of the range of a 64-bit integer"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 4294967296\n", 4, "vertex index 4294967296 is out of range"));
  EXPECT_TRUE(fails_at(v3 + "f -1 -2 -4\n", 4, "vertex index -4 reaches before the first vertex (3 defined so far)"));
  EXPECT_TRUE(fails_at("f -1 -2 -3\nv 0 0 0\n", 1, "reaches before the first vertex (0 defined so far)"));
  EXPECT_TRUE(fails_at(v3 + "f 1 1 2\n", 4, "face repeats vertex 1"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2 3 2\n", 4, "face repeats vertex 2"));
  EXPECT_TRUE(fails_at(v3 + "f 1 2\n", 4, "face has 2 vertices; a face needs at least 3"));
  EXPECT_TRUE(fails_at(v3 + "f\n", 4, "face has 0 vertices"));
}

TEST_F(ObjTest, BadTextureAndNormalReferences) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
  EXPECT_TRUE(fails_at(v3 + "f 1/1 2/1 3/7\n", 5, "texture coordinate index 7 is out of range (the file has 1)"));
  EXPECT_TRUE(fails_at(v3 + "f 1//1 2//1 3//1\n", 5, "normal index 1 is out of range (the file has 0)"));
  EXPECT_TRUE(fails_at(v3 + "f 1/-2 2/1 3/1\n", 5, "texture coordinate index -2 reaches before"));
  EXPECT_TRUE(fails_at(v3 + "f 1/0 2/1 3/1\n", 5, "texture coordinate index 0 is invalid"));
  for (const char* bad : {"1/", "1//", "/1", "1/1/1/1", "1/1/", "//"})
    EXPECT_TRUE(fails_at(v3 + "f " + bad + " 2 3\n", 5, "face vertex '" + std::string(bad) + "' is malformed"));
}

TEST_F(ObjTest, UnsupportedStatements) {
  EXPECT_TRUE(fails_at("v 0 0 0\nv 1 0 0\nl 1 2\n", 3, "line/point elements are not supported"));
  EXPECT_TRUE(fails_at("v 0 0 0\np 1\n", 2, "line/point elements are not supported"));
  EXPECT_TRUE(fails_at("v 0 0 0\ncurv 0 1 1 2\n", 2, "unknown OBJ statement 'curv'"));
  EXPECT_TRUE(fails_at("V 0 0 0\n", 1, "unknown OBJ statement 'V'"));
  EXPECT_TRUE(fails_at("usemtl\n", 1, "usemtl needs a name"));
  EXPECT_TRUE(fails_at("s maybe\n", 1, "smoothing group 'maybe'"));
  // No line continuation: the backslash is a (bad) fourth component.
  EXPECT_TRUE(fails_at("v 1 2 3 \\\n 4\n", 1, "vertex weight '\\' is not a number"));
}

TEST_F(ObjTest, LineNumbersCountCommentsAndBlankLines) {
  EXPECT_TRUE(fails_at("# c\n\nv 0 0 0\n\n# c\nv 1 2 a\n", 6, "coordinate 'a' is not a number"));
}

TEST_F(ObjTest, EmptyMissingAndFolder) {
  std::string msg = error("");
  EXPECT_NE(msg.find("m.obj: file is empty"), std::string::npos) << msg;
  EXPECT_THROW(read_obj(dir_ / "absent.obj"), InputError);
  try {
    read_obj(dir_ / "absent.obj");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.obj: cannot open: no such file"), std::string::npos) << e.what();
  }
  fs::create_directories(dir_ / "folder.obj");
  EXPECT_THROW(read_obj(dir_ / "folder.obj"), InputError);
}

TEST_F(ObjTest, ControlBytesInTokensAreEscapedInMessages) {
  std::string msg = error(std::string("v 1\x01 2 3\n"));
  EXPECT_NE(msg.find("'1\\x01'"), std::string::npos) << msg;
}

TEST_F(ObjTest, TheFirstBadFieldIsReported) {
  EXPECT_TRUE(fails_at("v a 0 b\n", 1, "coordinate 'a' is not a number"));
  EXPECT_TRUE(fails_at("v 0 0 0\nv 0 0 1\nv 1 0 0\nf 1 x 0\n", 4, "vertex index 'x'"));
}
