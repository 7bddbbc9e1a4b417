// rebuild_adjacency() and validate() on about 200K faces: exact counts, and the times printed
// (recorded as test properties) for the report; no time limit is asserted.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "surface/fracture_surface.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

double seconds_of(const auto& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void time_and_check(FractureSurface& s, const char* name) {
  const double rebuild = seconds_of([&] { rebuild_adjacency(s); });
  std::string message;
  const double check = seconds_of([&] { message = validate(s); });
  EXPECT_EQ(message, "");
  std::printf("%s: %zu faces, %zu edges: rebuild_adjacency %.3f s, validate %.3f s\n", name, s.faces.size(),
              s.edges.size(), rebuild, check);
  testing::Test::RecordProperty("rebuild_ms", int(rebuild * 1000.0));
  testing::Test::RecordProperty("validate_ms", int(check * 1000.0));
}

TEST(SurfaceScale, SheetOf200KFaces) {
  FractureSurface s = example_sheet(317);
  ASSERT_EQ(s.faces.size(), 2u * 316 * 316);
  time_and_check(s, "sheet");
  EXPECT_EQ(s.edges.size(), 2u * 316 * 317 + 316u * 316);
  EXPECT_EQ(s.component_count, 2u);
}

// A long cross: a quarter of its edges are non-manifold, so the radial sort is exercised too.
TEST(SurfaceScale, CrossOf200KFaces) {
  FractureSurface s = example_cross(25000);
  ASSERT_EQ(s.faces.size(), 200000u);
  time_and_check(s, "cross");
  EXPECT_EQ(s.component_count, 4u);
  std::size_t non_manifold = 0;
  for (std::uint8_t k : s.edge_special) non_manifold += k == kEdgeNonManifold;
  EXPECT_EQ(non_manifold, 25000u);
}

}  // namespace
}  // namespace fracref
