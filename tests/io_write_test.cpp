// write_mesh and read_mesh: bit-exact round trips in every format, properties and groups,
// dispatch on the extension, and the writer's refusals.
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

class WriteTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_io_write_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  fs::path dir_;
};

// Awkward doubles (extremes, subnormals, signed zero, 17-digit fractions) and deterministic
// random bit patterns, one coordinate each.
std::vector<double> awkward_doubles() {
  std::vector<double> d = {0.1, 1.0 / 3.0, -2.0 / 3.0, 0.30000000000000004, 123456789.12345679,
                           std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                           std::numeric_limits<double>::min(), std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(), -0.0, 0.0, 1e-310, 9007199254740993.0,
                           3.141592653589793, -1e300};
  std::mt19937_64 rng(20140810);
  while (d.size() < 300) {
    double v = std::bit_cast<double>(rng());
    if (std::isfinite(v)) d.push_back(v);
  }
  while (d.size() % 3 != 0) d.push_back(0.5);
  return d;
}

MeshSoup awkward_soup() {
  MeshSoup s;
  std::vector<double> d = awkward_doubles();
  for (std::size_t i = 0; i < d.size(); i += 3) s.positions.emplace_back(d[i], d[i + 1], d[i + 2]);
  for (std::uint32_t i = 0; i + 2 < s.positions.size(); i += 2) s.triangles.push_back({i, i + 2, i + 1});
  s.polygons = s.triangles.size();
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) s.triangle_polygon.push_back(t);
  return s;
}

void expect_bit_exact(const MeshSoup& a, const MeshSoup& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(a.positions[i][k]), std::bit_cast<std::uint64_t>(b.positions[i][k]))
          << "vertex " << i << " axis " << k << ": " << a.positions[i][k] << " vs " << b.positions[i][k];
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.triangle_polygon, b.triangle_polygon);
  EXPECT_EQ(a.polygons, b.polygons);
}

MeshSoup square_with_properties() {
  MeshSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.triangle_polygon = {0, 1};
  s.polygons = 2;
  s.vertex_properties = {{"w0", PropertyType::Float32, {0.25, -1.5, 3.0, 1e-3f}},
                         {"label", PropertyType::UInt8, {0, 255, 7, 1}},
                         {"weight", PropertyType::Float64, {0.1, 1.0 / 3.0, -0.0, 1e300}}};
  s.face_properties = {{"front", PropertyType::Int32, {-1, 2147483647}},
                       {"back", PropertyType::Int32, {-2147483648.0, 5}},
                       {"tag", PropertyType::Int8, {-128, 127}},
                       {"mask", PropertyType::UInt32, {4294967295.0, 0}},
                       {"s", PropertyType::Int16, {-32768, 32767}},
                       {"u", PropertyType::UInt16, {65535, 1}}};
  return s;
}

void expect_same_columns(const std::vector<PropertyColumn>& a, const std::vector<PropertyColumn>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].type, b[i].type) << a[i].name;
    EXPECT_EQ(a[i].values, b[i].values) << a[i].name;
  }
}

}  // namespace

TEST_F(WriteTest, SeventeenDigitCoordinatesSurviveEveryFormatBitForBit) {
  MeshSoup s = awkward_soup();
  for (const char* name : {"a.obj", "a.off", "a.ply"}) {
    write_mesh(dir_ / name, s, {.ply_binary = false});
    SCOPED_TRACE(name);
    expect_bit_exact(s, read_mesh(dir_ / name));
  }
  write_mesh(dir_ / "b.ply", s);
  expect_bit_exact(s, read_mesh(dir_ / "b.ply"));
}

TEST_F(WriteTest, TextFormatsUseSeventeenSignificantDigits) {
  MeshSoup s;
  s.positions = {{0.1, -0.0, 1.0 / 3.0}};
  write_mesh(dir_ / "p.obj", s);
  EXPECT_NE(slurp(dir_ / "p.obj").find("v 0.10000000000000001 -0 0.33333333333333331\n"), std::string::npos);
  write_mesh(dir_ / "p.off", s);
  EXPECT_EQ(slurp(dir_ / "p.off"), "OFF\n1 0 0\n0.10000000000000001 -0 0.33333333333333331\n");
}

TEST_F(WriteTest, BinaryPlyStoresLittleEndianDoubles) {
  MeshSoup s;
  s.positions = {{1.0, 2.0, -0.5}};
  write_mesh(dir_ / "p.ply", s);
  std::string bytes = slurp(dir_ / "p.ply");
  ASSERT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  ASSERT_NE(bytes.find("property double x\nproperty double y\nproperty double z\n"), std::string::npos);
  std::string body = bytes.substr(bytes.find("end_header\n") + 11);
  ASSERT_EQ(body.size(), 24u);
  EXPECT_EQ(body.substr(0, 8), std::string("\0\0\0\0\0\0\xf0\x3f", 8));  // 1.0
}

TEST_F(WriteTest, PropertiesRoundTripThroughAsciiAndBinaryPly) {
  MeshSoup s = square_with_properties();
  for (bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    write_mesh(dir_ / "p.ply", s, {.ply_binary = binary});
    MeshSoup r = read_ply(dir_ / "p.ply");
    expect_bit_exact(s, r);
    expect_same_columns(s.vertex_properties, r.vertex_properties);
    expect_same_columns(s.face_properties, r.face_properties);
  }
  // OBJ and OFF leave the properties out.
  write_mesh(dir_ / "p.obj", s);
  EXPECT_TRUE(read_mesh(dir_ / "p.obj").vertex_properties.empty());
}

TEST_F(WriteTest, GroupsRoundTripThroughObj) {
  MeshSoup s = awkward_soup();
  s.groups = {"outside", "piece 1", "default"};
  for (std::size_t t = 0; t < s.triangles.size(); ++t) s.triangle_group.push_back(t < 10 ? 0 : (t < 30 ? 1 : 2));
  s.triangle_group[40] = 0;
  write_mesh(dir_ / "g.obj", s);
  MeshSoup r = read_obj(dir_ / "g.obj");
  expect_bit_exact(s, r);
  EXPECT_EQ(r.groups, s.groups);
  EXPECT_EQ(r.triangle_group, s.triangle_group);
}

TEST_F(WriteTest, ReadMeshDispatchesOnTheExtensionCaseInsensitively) {
  MeshSoup s = square_with_properties();
  for (const char* name : {"u.OBJ", "u.Off", "u.PLY"}) {
    write_mesh(dir_ / name, s);
    EXPECT_EQ(read_mesh(dir_ / name).triangles, s.triangles) << name;
  }
  // The content decides nothing: a PLY body under an .obj name is an OBJ error.
  fs::copy_file(dir_ / "u.PLY", dir_ / "ply_inside.obj");
  EXPECT_THROW(read_mesh(dir_ / "ply_inside.obj"), InputError);
}

TEST_F(WriteTest, UnknownOrMissingExtensionsAreInputErrors) {
  for (const char* name : {"mesh.stl", "mesh", "mesh.obj.bak"}) {
    std::ofstream(dir_ / name) << "v 0 0 0\n";
    try {
      read_mesh(dir_ / name);
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.rfind((dir_ / name).string() + ": ", 0), 0u) << msg;
      EXPECT_NE(msg.find("must be .obj, .off or .ply"), std::string::npos) << msg;
    }
    EXPECT_THROW(write_mesh(dir_ / (std::string(name) + "2"), MeshSoup{}), InputError);
  }
  try {
    read_mesh(dir_ / "mesh.stl");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported extension '.stl'"), std::string::npos) << e.what();
  }
}

TEST_F(WriteTest, ReadMeshReportsMissingAndEmptyFiles) {
  try {
    read_mesh(dir_ / "gone.off");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "gone.off").string() + ": cannot open: no such file");
  }
  std::ofstream(dir_ / "empty.ply").close();
  EXPECT_THROW(read_mesh(dir_ / "empty.ply"), InputError);
}

TEST_F(WriteTest, WriterRefusesWhatWouldNotReadBack) {
  MeshSoup bad = square_with_properties();
  bad.vertex_properties[1].values[0] = 256;  // uchar
  EXPECT_THROW(write_mesh(dir_ / "x.ply", bad), RunError);
  bad = square_with_properties();
  bad.face_properties[0].values[0] = 1.5;  // int
  EXPECT_THROW(write_mesh(dir_ / "x.ply", bad), RunError);
  bad = square_with_properties();
  bad.vertex_properties[0].values.pop_back();
  EXPECT_THROW(write_mesh(dir_ / "x.ply", bad), RunError);
  bad = square_with_properties();
  bad.vertex_properties[0].name = "x";
  EXPECT_THROW(write_mesh(dir_ / "x.ply", bad), RunError);
  bad = square_with_properties();
  bad.face_properties[1].name = "two words";
  EXPECT_THROW(write_mesh(dir_ / "x.ply", bad), RunError);
  bad = square_with_properties();
  bad.positions[2].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_mesh(dir_ / "x.off", bad), RunError);
  bad = square_with_properties();
  bad.triangles[1][2] = 4;
  EXPECT_THROW(write_mesh(dir_ / "x.obj", bad), RunError);
  bad = square_with_properties();
  bad.groups = {"a # b"};
  bad.triangle_group = {0, 0};
  EXPECT_THROW(write_mesh(dir_ / "x.obj", bad), RunError);
  bad.groups = {"a"};
  bad.triangle_group = {0, 1};
  EXPECT_THROW(write_mesh(dir_ / "x.obj", bad), RunError);
  EXPECT_FALSE(fs::exists(dir_ / "x.ply"));
  EXPECT_FALSE(fs::exists(dir_ / "x.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "x.off"));
}

TEST_F(WriteTest, WritingReplacesTheFileAndLeavesNoTemporaries) {
  MeshSoup s = square_with_properties();
  std::ofstream(dir_ / "r.off") << "old";
  write_mesh(dir_ / "r.off", s);
  EXPECT_EQ(read_off(dir_ / "r.off").triangles, s.triangles);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u);
}

TEST_F(WriteTest, UnreadableFileIsAnInputError) {
  fs::path p = dir_ / "locked.obj";
  std::ofstream(p) << "v 0 0 0\n";
  fs::permissions(p, fs::perms::none);
  if (std::ifstream(p).good()) GTEST_SKIP() << "this user can read any file (root)";
  try {
    read_mesh(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ": cannot open for reading: Permission denied");
  }
}

TEST_F(WriteTest, FolderIsAnInputError) {
  fs::create_directories(dir_ / "folder.ply");
  try {
    read_mesh(dir_ / "folder.ply");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "folder.ply").string() + ": cannot open: it is a directory");
  }
}
