// The CCD ground-truth sample of Wang et al. 2021 (FRACREF_SHARED_DIR/data/ccd/sample-queries):
// a conservative CCD must report every true collision. False positives are counted and printed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geom/ccd.hpp"

namespace {

namespace fs = std::filesystem;
using glm::dvec3;

struct Query {
  dvec3 x[8];
  bool truth = false;
};

// An integer written in decimal, converted to the double of the same value; false when that
// value is not exactly a double. strtod rounds correctly and "%.0f" prints a double's exact
// integer value, so the round trip is an exactness check.
bool exact_integer(const std::string& text, double& out) {
  std::string digits = text;
  bool negative = false;
  if (!digits.empty() && (digits[0] == '-' || digits[0] == '+')) {
    negative = digits[0] == '-';
    digits.erase(0, 1);
  }
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size() - 1));
  const double magnitude = std::strtod(digits.c_str(), nullptr);
  char printed[400];
  std::snprintf(printed, sizeof printed, "%.0f", magnitude);
  if (digits != printed) return false;
  out = negative ? -magnitude : magnitude;
  return true;
}

// numerator / denominator as an exact double; the denominator must be a power of two.
bool exact_rational(const std::string& num, const std::string& den, double& out) {
  double n = 0, d = 0;
  if (!exact_integer(num, n) || !exact_integer(den, d) || !(d > 0)) return false;
  int e = 0;
  if (std::frexp(d, &e) != 0.5) return false;
  out = n / d;
  return out * d == n;  // scaling by a power of two is exact unless the quotient lost bits
}

std::vector<Query> read_queries(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Query> queries;
  std::string line;
  std::size_t row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    const std::string where = file.string() + ":" + std::to_string(row);
    if (cells.size() != 7) {
      ADD_FAILURE() << where << ": expected 7 columns, got " << cells.size();
      return {};
    }
    if ((row - 1) % 8 == 0) queries.emplace_back();
    Query& q = queries.back();
    dvec3& p = q.x[(row - 1) % 8];
    for (int k = 0; k < 3; ++k)
      if (!exact_rational(cells[2 * k], cells[2 * k + 1], p[k])) {
        ADD_FAILURE() << where << ": " << cells[2 * k] << "/" << cells[2 * k + 1] << " is not exactly a double";
        return {};
      }
    const bool truth = cells[6] == "1";
    if (cells[6] != "0" && cells[6] != "1") ADD_FAILURE() << where << ": ground truth '" << cells[6] << "'";
    if ((row - 1) % 8 == 0) q.truth = truth;
    if (q.truth != truth) ADD_FAILURE() << where << ": ground truth differs within one query";
  }
  if (row % 8 != 0) ADD_FAILURE() << file << ": " << row << " rows, not a multiple of 8";
  return queries;
}

bool run_query(const Query& q, bool vertex_face, const fracref::CcdOptions& options) {
  const dvec3* x = q.x;
  if (vertex_face) return fracref::ccd_vertex_triangle(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], options);
  return fracref::ccd_edge_edge(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], options);
}

TEST(GeomCcdBenchmark, NoFalseNegativesOnTheGroundTruthSample) {
  const fs::path root = fs::path(FRACREF_SHARED_DIR) / "data" / "ccd" / "sample-queries";
  if (!fs::is_directory(root)) GTEST_SKIP() << root << " is absent";
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file() && entry.path().extension() == ".csv") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());

  const fracref::CcdOptions options;  // min_distance 0, tolerance 1e-6
  std::size_t total = 0, collisions = 0, false_negatives = 0, false_positives = 0;
  double seconds = 0.0;
  std::printf("%-60s %7s %7s %7s %7s %9s\n", "file", "queries", "true", "FN", "FP", "ms");
  for (const fs::path& file : files) {
    const std::string name = fs::relative(file, root).string();
    const bool vertex_face = name.find("vertex-face") != std::string::npos;
    ASSERT_TRUE(vertex_face || name.find("edge-edge") != std::string::npos) << name;
    const auto queries = read_queries(file);
    ASSERT_FALSE(queries.empty()) << name;
    std::size_t fn = 0, fp = 0, positives = 0;
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const bool hit = run_query(queries[i], vertex_face, options);
      positives += queries[i].truth;
      if (queries[i].truth && !hit) {
        ++fn;
        ADD_FAILURE() << name << ": query " << i << " is a collision and was missed";
      }
      fp += !queries[i].truth && hit;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-60s %7zu %7zu %7zu %7zu %9.2f\n", name.c_str(), queries.size(), positives, fn, fp, ms);
    total += queries.size();
    collisions += positives;
    false_negatives += fn;
    false_positives += fp;
    seconds += ms / 1000.0;
  }
  std::printf("total: %zu queries, %zu collisions, %zu false negatives, %zu false positives, %.3f s\n", total,
              collisions, false_negatives, false_positives, seconds);
  RecordProperty("queries", static_cast<int>(total));
  RecordProperty("false_positives", static_cast<int>(false_positives));
  EXPECT_EQ(false_negatives, 0u);
  EXPECT_EQ(total, 5409u);       // the sample as documented in its README
  EXPECT_EQ(collisions, 435u);   // 248 vertex-face + 187 edge-edge
}

TEST(GeomCcdBenchmark, RationalParsingIsExactOrRefused) {
  double v = 0;
  EXPECT_TRUE(exact_rational("6004799503160661", "18014398509481984", v));
  EXPECT_EQ(v, 6004799503160661.0 / 18014398509481984.0);
  EXPECT_TRUE(exact_rational("-1", "162259276829213363391578010288128", v));  // 2^-107
  EXPECT_EQ(v, -std::ldexp(1.0, -107));
  EXPECT_FALSE(exact_rational("9007199254740993", "1", v));  // 2^53 + 1: not a double
  EXPECT_FALSE(exact_rational("1", "3", v));                 // not a power of two
  EXPECT_FALSE(exact_rational("1x", "1", v));
}

}  // namespace
