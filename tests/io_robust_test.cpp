// Seeded mutations of valid OBJ, OFF and PLY files: every reader either returns a consistent
// soup or throws InputError with a located message — never another exception, never a soup
// that breaks its own invariants.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "io/mesh_io.hpp"
#include "io/mesh_stats.hpp"
#include "util/error.hpp"
#include "util/input_size.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

class RobustTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("fracref_io_robust_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Reads `bytes` as `name`; returns "" when the outcome is acceptable, else what went wrong.
  // Sets rejected_ when the reader threw InputError.
  std::string check(const std::string& name, const std::string& bytes) {
    fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
    rejected_ = false;
    try {
      return consistent(read_mesh(p));
    } catch (const InputError& e) {
      rejected_ = true;
      std::string msg = e.what();
      return msg.rfind(p.string() + ":", 0) == 0 ? "" : "unlocated message: " + msg;
    } catch (const std::exception& e) {
      return std::string("unexpected exception: ") + e.what();
    }
  }

  static std::string consistent(const MeshSoup& s) {
    for (const auto& p : s.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "non-finite position";
    for (const auto& t : s.triangles) {
      for (std::uint32_t v : t)
        if (v >= s.positions.size()) return "index out of range";
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return "degenerate triangle";
    }
    if (s.triangle_polygon.size() != s.triangles.size()) return "triangle_polygon size";
    if (!s.triangle_group.empty() && s.triangle_group.size() != s.triangles.size()) return "triangle_group size";
    for (const auto& c : s.vertex_properties)
      if (c.values.size() != s.positions.size()) return "vertex property size";
    for (const auto& c : s.face_properties)
      if (c.values.size() != s.triangles.size()) return "face property size";
    mesh_stats(s);
    return "";
  }

  // Runs `rounds` seeded mutations of `bytes`: byte replacements, deletions, insertions and
  // truncations drawn from characters that matter to the parsers.
  void mutate_and_check(const std::string& name, const std::string& bytes, unsigned seed, int rounds) {
    static const std::string kAlphabet = std::string("0123456789-+. \n\r\t/#e,naxf") + std::string("\0\xff\x7f", 3);
    std::mt19937 rng(seed);
    int rejected = 0;
    for (int r = 0; r < rounds; ++r) {
      std::string m = bytes;
      int edits = 1 + static_cast<int>(rng() % 3);
      for (int e = 0; e < edits && !m.empty(); ++e) {
        std::size_t at = rng() % m.size();
        switch (rng() % 4) {
          case 0: m[at] = kAlphabet[rng() % kAlphabet.size()]; break;
          case 1: m.erase(at, 1 + rng() % 4); break;
          case 2: m.insert(at, 1, kAlphabet[rng() % kAlphabet.size()]); break;
          case 3: m.resize(at); break;
        }
      }
      std::string problem = check(name, m);
      ASSERT_EQ(problem, "") << "round " << r << " of " << name << ":\n" << m;
      rejected += rejected_;
    }
    // The mutations must actually exercise the error paths.
    EXPECT_GT(rejected, rounds / 4) << name;
  }

  fs::path dir_;
  bool rejected_ = false;
};

MeshSoup sample_soup() {
  MeshSoup s;
  s.positions = {{0.1, 0, 0}, {1, 0, 1.0 / 3.0}, {1, 1, 0}, {0, 1, -2.5}, {0.5, 0.5, 1e-7}};
  s.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  s.triangle_polygon = {0, 1, 2, 3};
  s.polygons = 4;
  s.vertex_properties = {{"w0", PropertyType::Float32, {0.5, 1, 2, 3, 4}}};
  s.face_properties = {{"front", PropertyType::Int32, {1, 2, -1, 0}}, {"back", PropertyType::UInt8, {0, 1, 2, 3}}};
  s.groups = {"a", "b"};
  s.triangle_group = {0, 0, 1, 1};
  return s;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_F(RobustTest, MutatedObj) {
  write_mesh(dir_ / "base.obj", sample_soup());
  std::string text = slurp(dir_ / "base.obj") + "vt 0 1\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\n";
  ASSERT_EQ(check("m.obj", text), "");
  mutate_and_check("m.obj", text, 1, 250);
}

TEST_F(RobustTest, MutatedOff) {
  write_mesh(dir_ / "base.off", sample_soup());
  std::string text = slurp(dir_ / "base.off");
  mutate_and_check("m.off", text, 2, 250);
}

TEST_F(RobustTest, MutatedAsciiPly) {
  write_mesh(dir_ / "base.ply", sample_soup(), {.ply_binary = false});
  mutate_and_check("m.ply", slurp(dir_ / "base.ply"), 3, 250);
}

TEST_F(RobustTest, MutatedBinaryPly) {
  write_mesh(dir_ / "base.ply", sample_soup());
  mutate_and_check("m.ply", slurp(dir_ / "base.ply"), 4, 250);
}

// A file larger than fracref reads whole is refused by its size before a byte is read (a 30 GB
// OBJ ended in a bare std::bad_alloc). The file is sparse: it costs no disk and no memory.
TEST_F(RobustTest, HugeFileIsRefusedBySizeBeforeReading) {
  const std::uint64_t size = max_input_file_bytes() + 1;
  for (const char* name : {"huge.obj", "huge.off", "huge.ply"}) {
    SCOPED_TRACE(name);
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << "v 0 0 0\n";
    fs::resize_file(p, size);
    try {
      read_mesh(p);
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), p.string() + ": the file is " + size_text(size) + ", more than the " +
                                           size_text(max_input_file_bytes()) + " fracref reads whole on this machine (" +
                                           size_text(physical_memory_bytes()) + " of memory)");
    }
    fs::remove(p);
  }
}

TEST(InputSize, SizeText) {
  EXPECT_EQ(size_text(0), "0 bytes");
  EXPECT_EQ(size_text(1), "1 byte");
  EXPECT_EQ(size_text(999), "999 bytes");
  EXPECT_EQ(size_text(1500), "1.5 KB");
  EXPECT_EQ(size_text(2'100'000'000), "2.1 GB");
  EXPECT_EQ(size_text(30'000'000'000), "30.0 GB");
}

TEST(InputSize, LimitIsAQuarterOfTheMemoryAndAtLeast256MiB) {
  const std::uint64_t memory = physical_memory_bytes();
  ASSERT_GT(memory, 0u);
  EXPECT_EQ(max_input_file_bytes(), std::max<std::uint64_t>(memory / 4, std::uint64_t(256) << 20));
}
