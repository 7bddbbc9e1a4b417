// The strict OFF reader: accepted files with exact counts, and every malformed case with the
// file, line and cause in its message.
#include <unistd.h>

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

class OffTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_io_off_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& text) {
    fs::path p = dir_ / "m.off";
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  MeshSoup read(const std::string& text) { return read_off(write(text)); }

  ::testing::AssertionResult fails_at(const std::string& text, std::size_t line, const std::string& cause) {
    fs::path p = write(text);
    std::string msg = "<no error>";
    try {
      read_off(p);
    } catch (const InputError& e) {
      msg = e.what();
    }
    std::string where = p.string() + ":" + std::to_string(line) + ": ";
    if (msg.rfind(where, 0) == 0 && msg.find(cause) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message '" << msg << "' lacks '" << where << "' or '" << cause << "'";
  }

  fs::path dir_;
};

const std::string kTetra =
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
const std::string kHead = "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";  // face on line 7

using Tri = std::array<std::uint32_t, 3>;

}  // namespace

TEST_F(OffTest, TetrahedronIsReadExactly) {
  MeshSoup s = read(kTetra);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.triangles[0], (Tri{0, 2, 1}));
  EXPECT_EQ(s.triangles[3], (Tri{2, 0, 3}));
  EXPECT_EQ(s.polygons, 4u);
  MeshStats st = mesh_stats(s);
  EXPECT_TRUE(st.closed);
  EXPECT_EQ(st.components, 1u);
  EXPECT_EQ(st.boundary_edges, 0u);
}

TEST_F(OffTest, QuadIsFanTriangulated) {
  MeshSoup s = read("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(s.triangles[1], (Tri{0, 2, 3}));
  EXPECT_EQ(s.polygons, 1u);
  EXPECT_EQ(s.polygons_triangulated, 1u);
  EXPECT_EQ(s.triangle_polygon, (std::vector<std::uint32_t>{0, 0}));
}

TEST_F(OffTest, CommentsBlankLinesCrlfAndCountsOnTheKeywordLine) {
  MeshSoup a = read("# made by hand\nOFF # keyword\n\n4 4 0\n# vertices\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\n"
                    "3 0 2 1\n3 0 1 3 # a comment\n3 1 2 3\n3 2 0 3\n\n# end\n");
  MeshSoup b = read("OFF 4 4 6\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n3 0 2 1\r\n3 0 1 3\r\n3 1 2 3\r\n3 2 0 3\r\n");
  MeshSoup c = read(kTetra);
  EXPECT_EQ(read("\xEF\xBB\xBF" + kTetra).triangles, c.triangles);
  EXPECT_EQ(a.triangles, c.triangles);
  EXPECT_EQ(b.triangles, c.triangles);
  EXPECT_EQ(b.positions, c.positions);
}

TEST_F(OffTest, UnusedVerticesAndExactCoordinatesAreKept) {
  MeshSoup s = read("OFF\n5 1 0\n0.1 0.2 0.30000000000000004\n1 0 0\n0 1 0\n9 9 9\n+1e-300 -0 2.5\n3 0 1 2\n");
  ASSERT_EQ(s.positions.size(), 5u);
  EXPECT_EQ(s.positions[0], glm::dvec3(0.1, 0.2, 0.1 + 0.2));
  EXPECT_EQ(s.positions[4].x, 1e-300);
  EXPECT_EQ(mesh_stats(s).components, 1u);
}

TEST_F(OffTest, HeaderProblems) {
  EXPECT_TRUE(fails_at("# only a comment\n", 1, "file has no OFF header"));
  EXPECT_TRUE(fails_at("ply\n", 1, "not an OFF file (the first line must be 'OFF', found 'ply')"));
  EXPECT_TRUE(fails_at("COFF\n1 0 0\n0 0 0 1 1 1 1\n", 1, "OFF variant 'COFF' is not supported"));
  EXPECT_TRUE(fails_at("NOFF\n", 1, "OFF variant 'NOFF'"));
  EXPECT_TRUE(fails_at("OFF BINARY\n", 1, "binary OFF is not supported"));
  EXPECT_TRUE(fails_at("OFF\n", 1, "file ends before the counts line"));
  EXPECT_TRUE(fails_at("OFF\n3 1\n", 2, "counts line needs 3 numbers (vertices faces edges), got 2"));
  EXPECT_TRUE(fails_at("OFF\n3 1 0 0\n", 2, "got 4"));
  EXPECT_TRUE(fails_at("OFF\n-3 1 0\n", 2, "vertex count '-3' is negative"));
  EXPECT_TRUE(fails_at("OFF\n3 x 0\n", 2, "face count 'x' is not an integer"));
  EXPECT_TRUE(fails_at("OFF\n3 1.0 0\n", 2, "face count '1.0' is not an integer"));
  EXPECT_TRUE(fails_at("OFF\n99999999999 1 0\n", 2, "is too large"));
}

TEST_F(OffTest, CountsThatDoNotMatchTheData) {
  EXPECT_TRUE(fails_at("OFF\n4 1 0\n0 0 0\n1 0 0\n", 4, "file ends after 2 of the 4 vertices announced in the header"));
  EXPECT_TRUE(fails_at(kHead, 6, "file ends after 0 of the 1 faces announced in the header"));
  EXPECT_TRUE(fails_at(kHead + "3 0 1 2\n3 0 1 3\n", 8, "extra data after the 1 faces announced in the header"));
  // With too many vertex lines the first extra one is read as a face.
  EXPECT_TRUE(fails_at(kHead + "0 0 2\n3 0 1 2\n", 7, "face has 0 vertices"));
}

TEST_F(OffTest, BadCoordinates) {
  const std::string h = "OFF\n3 0 0\n0 0 0\n";
  EXPECT_TRUE(fails_at(h + "1 nan 0\n0 1 0\n", 4, "coordinate 'nan' is not finite"));
  EXPECT_TRUE(fails_at(h + "1 -inf 0\n0 1 0\n", 4, "coordinate '-inf' is not finite"));
  EXPECT_TRUE(fails_at(h + "1e999 0 0\n0 1 0\n", 4, "coordinate '1e999' is out of the range of double"));
  EXPECT_TRUE(fails_at(h + "1 0\n0 1 0\n", 4, "vertex needs 3 coordinates, got 2"));
  EXPECT_TRUE(fails_at(h + "1 0 0 1 0\n0 1 0\n", 4, "vertex needs 3 coordinates, got 5"));
  EXPECT_TRUE(fails_at(h + "1,5 0 0\n0 1 0\n", 4, "comma used as decimal separator"));
  EXPECT_TRUE(fails_at(h + "1 0 0z\n0 1 0\n", 4, "coordinate '0z' is not a number (trailing 'z')"));
}

TEST_F(OffTest, BadFaces) {
  EXPECT_TRUE(fails_at(kHead + "3 0 1 4\n", 7, "face index 4 is out of range (the file has 4 vertices; OFF indices start at 0)"));
  EXPECT_TRUE(fails_at(kHead + "3 0 -1 2\n", 7, "face index -1 is negative"));
  EXPECT_TRUE(fails_at(kHead + "3 0 1 b\n", 7, "face index 'b' is not an integer"));
  EXPECT_TRUE(fails_at(kHead + "3 0 1 1\n", 7, "face repeats vertex 1"));
  EXPECT_TRUE(fails_at(kHead + "2 0 1\n", 7, "face has 2 vertices; a face needs at least 3"));
  EXPECT_TRUE(fails_at(kHead + "4 0 1 2\n", 7, "face announces 4 vertices but lists 3"));
  EXPECT_TRUE(fails_at(kHead + "3 0 1 2 255 0 0\n", 7, "face colors are not supported"));
  EXPECT_TRUE(fails_at(kHead + "three 0 1 2\n", 7, "face vertex count 'three' is not an integer"));
}

TEST_F(OffTest, EmptyAndMissingFiles) {
  fs::path p = write("");
  try {
    read_off(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ": file is empty");
  }
  EXPECT_THROW(read_off(dir_ / "nothing.off"), InputError);
}
