// The strength grid file (scenes/INPUTS.md, "Strength grid"): round trips in both formats, and
// every malformed file refused with a message naming the file, the line or byte, and the cause.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "field/grid_file.hpp"
#include "util/error.hpp"
#include "util/input_size.hpp"

using namespace fracref;
namespace fs = std::filesystem;

namespace {

struct Temp {
  fs::path dir;
  Temp() {
    static int n = 0;
    dir = fs::temp_directory_path() / ("fracref_gridfile_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Temp() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  fs::path write(const std::string& bytes) const {
    fs::path p = dir / "s.grid";
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
};

Grid3 sample_grid() {
  Grid3 g;
  g.dims = {3, 2, 4};
  g.origin = {-1.0, 0.5, -4.25};
  g.cell = 0.125;
  for (std::size_t i = 0; i < g.size(); ++i) g.values.push_back(float(i) * 0.1f - 0.7f + (i == 5 ? 1e-7f : 0.0f));
  return g;
}

const std::string kHeader = "fracref-grid 1\ndims 2 2 2\norigin 0 0 0\ncell 0.5\nformat text\nend_header\n";

// The message of the InputError read_strength_grid() throws on `bytes` (empty if none).
std::string error_of(const std::string& bytes) {
  Temp t;
  fs::path p = t.write(bytes);
  try {
    read_strength_grid(p);
  } catch (const InputError& e) {
    std::string m = e.what();
    EXPECT_EQ(m.rfind(p.string(), 0), 0u) << m;  // the file is named first
    return m.substr(p.string().size());
  }
  return "";
}

std::string floats(std::size_t n, float v) {
  std::string s(4 * n, '\0');
  for (std::size_t i = 0; i < n; ++i) std::memcpy(&s[4 * i], &v, 4);  // the test host is little-endian
  return s;
}

}  // namespace

TEST(GridFile, BinaryRoundTripIsExact) {
  Temp t;
  Grid3 g = sample_grid();
  write_strength_grid(t.dir / "b.grid", g, true);
  Grid3 r = read_strength_grid(t.dir / "b.grid");
  EXPECT_EQ(r.dims, g.dims);
  EXPECT_EQ(r.origin, g.origin);
  EXPECT_EQ(r.cell, g.cell);
  EXPECT_EQ(r.values, g.values);
  EXPECT_FALSE(fs::exists(t.dir / ("b.grid.tmp-" + std::to_string(::getpid()))));
}

TEST(GridFile, TextRoundTripIsExact) {
  Temp t;
  Grid3 g = sample_grid();
  write_strength_grid(t.dir / "t.grid", g, false);
  Grid3 r = read_strength_grid(t.dir / "t.grid");
  EXPECT_EQ(r.dims, g.dims);
  EXPECT_EQ(r.origin, g.origin);
  EXPECT_EQ(r.cell, g.cell);
  EXPECT_EQ(r.values, g.values);
}

TEST(GridFile, TextAcceptsCommentsBlankLinesAndAnyLayout) {
  Temp t;
  Grid3 g = read_strength_grid(t.write("fracref-grid 1  # magic\n\n# a comment\ndims 2 2 2\norigin -1 +2 3e-1\ncell 0.5\n"
                                       "format text\nend_header\n1 2 3\n\n4 # four\n5 6 7 8"));
  EXPECT_EQ(g.dims, glm::uvec3(2, 2, 2));
  EXPECT_EQ(g.origin, glm::dvec3(-1, 2, 0.3));
  ASSERT_EQ(g.values.size(), 8u);
  EXPECT_EQ(g.values[0], 1.0f);
  EXPECT_EQ(g.values[7], 8.0f);
}

TEST(GridFile, HeaderErrorsNameTheLine) {
  EXPECT_EQ(error_of("fracref-grid 2\n"), ":1: not a strength grid: the first line must be 'fracref-grid 1'");
  EXPECT_EQ(error_of("ply\n"), ":1: not a strength grid: the first line must be 'fracref-grid 1'");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2 2\nspacing 1\n"), ":3: unknown key 'spacing' (dims, origin, cell, format, end_header)");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2 2\norigin 0 0 0\nformat text\nend_header\n"),
            ":5: missing key 'cell' before 'end_header'");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2 2\n"), ":2: the header has no 'end_header' line");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 1 2\n"), ":2: key 'dims': '1' must be an integer in [2, 1024]");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2 1025\n"), ":2: key 'dims': '1025' must be an integer in [2, 1024]");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2.5 2\n"), ":2: key 'dims': '2.5' must be an integer in [2, 1024]");
  EXPECT_EQ(error_of("fracref-grid 1\ndims 2 2\n"), ":2: key 'dims' takes 3 value(s), got 2");
  EXPECT_EQ(error_of("fracref-grid 1\ncell 0\n"), ":2: key 'cell': '0' must be > 0");
  EXPECT_EQ(error_of("fracref-grid 1\ncell -0.5\n"), ":2: key 'cell': '-0.5' must be > 0");
  EXPECT_EQ(error_of("fracref-grid 1\norigin 0 nan 0\n"), ":2: key 'origin': 'nan' is not finite");
  EXPECT_EQ(error_of("fracref-grid 1\norigin 0 0,5 0\n"), ":2: key 'origin': '0,5' is not a number");
  EXPECT_EQ(error_of("fracref-grid 1\ncell 1\ncell 2\n"), ":3: key 'cell' is given twice");
  EXPECT_EQ(error_of("fracref-grid 1\nformat float64\n"), ":2: key 'format': 'float64' is not 'float32-le' or 'text'");
  EXPECT_EQ(error_of("fracref-grid 1\nend_header now\n"), ":2: 'end_header' takes no value");
}

// A NUL byte once stopped the tokenizer from advancing (a hang at 100% CPU): it is an error now.
TEST(GridFile, NulByteIsAnErrorNotAHang) {
  EXPECT_EQ(error_of(std::string("fracref-grid 1\n\0\n", 17)), ":2: unknown key '\0' (dims, origin, cell, format, end_header)");
  EXPECT_NE(error_of(kHeader + std::string("1 2 \0 4\n", 9)), "");
}

// A grid file too large to read whole is refused by its size (a sparse file: no disk, no memory).
TEST(GridFile, HugeFileIsRefusedBySize) {
  Temp t;
  const fs::path p = t.write("fracref-grid 1\n");
  fs::resize_file(p, max_input_file_bytes() + 1);
  try {
    read_strength_grid(p);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(p.string() + ": the file is " + size_text(max_input_file_bytes() + 1), 0), 0u);
  }
}

// Large dims over a short text do not reserve memory for every announced value.
TEST(GridFile, LargeDimsWithFewTextValuesIsTooFewNotAnAllocation) {
  EXPECT_EQ(error_of("fracref-grid 1\ndims 1024 1024 1024\norigin 0 0 0\ncell 1\nformat text\nend_header\n1 2 3\n"),
            ":7: too few values: 3 of the 1073741824 that dims give");
}

TEST(GridFile, TextValueErrorsNameTheLine) {
  EXPECT_EQ(error_of(kHeader + "1 2 3 4\n5 6 7\n"), ":8: too few values: 7 of the 8 that dims give");
  EXPECT_EQ(error_of(kHeader + "1 2 3 4\n5 6 7 8\n9\n"), ":9: too many values: '9' after the 8 of dims");
  EXPECT_EQ(error_of(kHeader + "1 2 nan 4\n"), ":7: value 'nan' is not finite");
  EXPECT_EQ(error_of(kHeader + "1 2 3 4\n5 inf 7 8\n"), ":8: value 'inf' is not finite");
  EXPECT_EQ(error_of(kHeader + "1 2 3x 4\n"), ":7: value '3x' is not a number");
  EXPECT_EQ(error_of(kHeader + "1 2 1e39 4 5 6 7 8\n"), ":7: value '1e39' is out of float range");
}

TEST(GridFile, BinaryErrorsNameTheByte) {
  const std::string h = "fracref-grid 1\ndims 2 2 2\norigin 0 0 0\ncell 0.5\nformat float32-le\nend_header\n";
  const std::string n = std::to_string(h.size());
  EXPECT_EQ(error_of(h + floats(7, 1.0f) + "ab"),
            ": byte " + std::to_string(h.size() + 30) + ": truncated binary data: 30 bytes for 8 float32 values (32 bytes needed)");
  EXPECT_EQ(error_of(h + floats(8, 1.0f) + "\n"), ": byte " + std::to_string(h.size() + 32) + ": 1 trailing bytes after the 8 values");
  std::string bad = floats(8, 1.0f);
  float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bad[12], &q, 4);
  EXPECT_EQ(error_of(h + bad), ": byte " + std::to_string(h.size() + 12) + ": value 3 is not finite");
  EXPECT_EQ(error_of(h), ": byte " + n + ": truncated binary data: 0 bytes for 8 float32 values (32 bytes needed)");
}

TEST(GridFile, MissingFileIsAnInputError) {
  Temp t;
  EXPECT_THROW(read_strength_grid(t.dir / "none.grid"), InputError);
}

TEST(GridFile, TheExampleOfInputsMdReads) {
  std::ifstream in(fs::path(FRACREF_SOURCE_DIR) / "scenes" / "INPUTS.md");
  std::string line, text;
  bool seen = false, inside = false;
  while (std::getline(in, line)) {
    if (inside && line == "```") break;
    if (inside) text += line + "\n";
    if (line == "<!-- file: strength.grid -->") seen = true;
    else if (seen && line == "```") inside = true;
  }
  ASSERT_FALSE(text.empty());
  Temp t;
  Grid3 g = read_strength_grid(t.write(text));
  EXPECT_EQ(g.dims, glm::uvec3(2, 2, 2));
  EXPECT_EQ(g.cell, 1.0);
  EXPECT_EQ(g.values, (std::vector<float>{1, 1, 1, 1, 0.25f, 0.25f, 0.25f, 0.25f}));
}
