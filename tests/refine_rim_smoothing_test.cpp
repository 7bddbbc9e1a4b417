// smooth_rim (refine/rim_smoothing.hpp): a sheet across the unit cube whose rim zig-zags up and
// down the cube's walls, as a coarse fracture of tetrahedra meets B.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pieces_test_support.hpp"
#include "refine/exterior.hpp"
#include "refine/rim_smoothing.hpp"
#include "refine_test_support.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

constexpr int kCells = 8;
constexpr float kZig = 0.05f;

// The 8x8 sheet at z = 0.5, its nodes on the cube's walls alternately kZig above and below.
FractureSurface zigzag_sheet() {
  return test::sheet_of(kCells, [](int i, int j) {
    const bool rim = i == 0 || j == 0 || i == kCells || j == kCells;
    return rim ? 0.5f + ((i + j) % 2 ? kZig : -kZig) : 0.5f;
  });
}

double zigzag(const FractureSurface& s) {
  double most = 0.0;
  for (std::size_t v = 0; v < s.positions.size(); ++v)
    if (s.vertex_flags[v] & kVertexBoundary) most = std::max(most, std::abs(double(s.positions[v].z) - 0.5));
  return most;
}

glm::dvec3 normal(const FractureSurface& s, const glm::uvec4& f) {
  const auto p = [&](std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); };
  return glm::cross(p(f.y) - p(f.x), p(f.z) - p(f.x));
}

}  // namespace

TEST(RimSmoothing, TheZigZagFlattensTheRimStaysOnBAndTheInsideStays) {
  const ExteriorSurface b = make_exterior(test::unit_cube(), "cube");
  FractureSurface s = zigzag_sheet();
  const FractureSurface before = s;
  ASSERT_NEAR(zigzag(s), kZig, 1e-6);
  const std::size_t moves = smooth_rim(s, b, {.passes = 3});
  EXPECT_GT(moves, 0u);
  EXPECT_LT(zigzag(s), 0.4 * kZig);
  EXPECT_EQ(validate(s), "");
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    if (s.vertex_flags[v] & kVertexBoundary)
      EXPECT_LT(b.squared_distance(glm::dvec3(glm::vec3(s.positions[v]))), 1e-12) << "rim vertex " << v << " left B";
    else
      EXPECT_EQ(s.positions[v], before.positions[v]) << "vertex " << v << " is not on the rim";
  }
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    EXPECT_GT(glm::dot(normal(s, s.faces[f]), normal(before, before.faces[f])), 0.0) << "face " << f << " turned over";
}

// Every move turns a face a little: with no turn allowed, nothing moves; with no pass, neither.
TEST(RimSmoothing, AMoveTheChecksRefuseIsNotMade) {
  const ExteriorSurface b = make_exterior(test::unit_cube(), "cube");
  FractureSurface s = zigzag_sheet();
  const std::vector<glm::vec4> start = s.positions;
  EXPECT_EQ(smooth_rim(s, b, {.passes = 3, .max_turn_degrees = 1e-3}), 0u);
  EXPECT_EQ(s.positions, start);
  EXPECT_EQ(smooth_rim(s, b, {.passes = 0}), 0u);
  EXPECT_EQ(s.positions, start);
}

// A sheet whose rim is already straight on B's flat walls stays where it is (up to rounding).
TEST(RimSmoothing, AStraightRimStays) {
  const ExteriorSurface b = make_exterior(test::unit_cube(), "cube");
  FractureSurface s = test::sheet(kCells, 0.5f);
  const std::vector<glm::vec4> start = s.positions;
  smooth_rim(s, b, {.passes = 3});
  for (std::size_t v = 0; v < s.positions.size(); ++v)
    EXPECT_LT(glm::distance(glm::vec3(s.positions[v]), glm::vec3(start[v])), 1e-6f) << "vertex " << v;
}

// Three sheets meeting along a junction (the T of surface_examples) in a box whose walls hold
// their rims; the horizontal sheet's rim on the walls x = ±1 zig-zags, and the junction's ends on
// the walls y = 0 and y = 6 are pushed off the mean of their three rim neighbours. The smoothing
// flattens the zig-zag and moves each junction end toward that mean, along its wall, the three
// sheets with it; S stays valid, the sheets in their order around the junction (validate).
TEST(RimSmoothing, AJunctionsEndsOnBMoveWithTheSheetsRims) {
  const int cells = 6;
  const ExteriorSurface b = make_exterior(pieces_test::box(glm::dvec3(-1.0, 0.0, -1.0), glm::dvec3(1.0, cells, 1.0), 6), "box");
  FractureSurface s = example_t_junction(cells);
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    glm::vec4& p = s.positions[v];
    if (std::abs(p.x) == 1.0f && p.y > 0.0f && p.y < float(cells)) p.z = int(p.y) % 2 ? kZig : -kZig;
    if ((s.vertex_flags[v] & kVertexNonManifold) && (s.vertex_flags[v] & kVertexBoundary)) p.x = 0.15f;
  }
  ASSERT_EQ(validate(s), "");
  const std::vector<glm::vec4> start = s.positions;
  EXPECT_GT(smooth_rim(s, b, {.passes = 3}), 0u);
  EXPECT_EQ(validate(s), "");
  int junction_ends = 0;
  double zig = 0.0;
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    if (!(s.vertex_flags[v] & kVertexBoundary)) continue;
    EXPECT_LT(b.squared_distance(glm::dvec3(glm::vec3(s.positions[v]))), 1e-12) << "rim vertex " << v << " left B";
    if (s.vertex_flags[v] & kVertexNonManifold) {
      // Its neighbours (-1, y, 0), (1, y, 0), (0, y, 1) have their mean at x = 0: it moves back.
      EXPECT_LT(std::abs(s.positions[v].x), 0.5f * start[v].x) << "junction end " << v;
      EXPECT_EQ(s.positions[v].y, start[v].y) << "junction end " << v << " left its wall";
      ++junction_ends;
    }
    if (std::abs(start[v].x) == 1.0f) zig = std::max(zig, std::abs(double(s.positions[v].z)));
  }
  EXPECT_EQ(junction_ends, 2);
  EXPECT_LT(zig, 0.5 * kZig);
}

}  // namespace fracref
