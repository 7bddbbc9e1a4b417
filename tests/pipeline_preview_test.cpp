// preview.png shows every piece's fracture faces: a box cut in two by a flat sheet, whose two
// fracture faces look in opposite directions (no one camera on the pieces in place sees both).
#include <gtest/gtest.h>

#include <cmath>

#include "pieces_test_support.hpp"
#include "pipeline/job_outputs.hpp"
#include "pipeline/surface_preview.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

using namespace pieces_test;

// Pixels whose hue is piece 0's colour (red) and piece 1's (blue), lit or not; the exterior and
// the background are grey.
std::pair<std::size_t, std::size_t> piece_pixels(const Image& im) {
  std::size_t red = 0, blue = 0;
  for (std::size_t i = 0; i + 2 < im.rgb.size(); i += 3) {
    const int r = im.rgb[i], b = im.rgb[i + 2];
    red += r > b + 40;
    blue += b > r + 40;
  }
  return {red, blue};
}

TEST(PiecesPreview, BothSidesOfACutAreSeen) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  const PieceSet set = build_pieces(example_sheet(4), b);
  ASSERT_EQ(set.pieces.size(), 2u);
  const Image im = preview_pieces(set);
  EXPECT_EQ(im.width, 1600);
  EXPECT_EQ(im.height, 1000);
  const auto [red, blue] = piece_pixels(im);
  const std::size_t pixels = std::size_t(im.width) * std::size_t(im.height);
  // Each fracture face (3 × 3 of a 3 × 3 × 1 half box) fills a good part of its half picture.
  EXPECT_GT(red, pixels / 20);
  EXPECT_GT(blue, pixels / 20);
}

TEST(PreviewView, TurnsTowardsTheStepsOfABreakThatFacesTheView) {
  const glm::dvec3 view(0.0, 0.0, 1.0);
  // A flat break: seen face-on.
  EXPECT_EQ(towards_walls({{0, 0, 4}, {0, 0, -1}}, view), view);
  // Steps across it, 10% of the area, most facing +x: turned 0.6 rad towards +x.
  const glm::dvec3 stepped = towards_walls({{0, 0, 9}, {0.7, 0, 0}, {-0.3, 0, 0}}, view);
  EXPECT_NEAR(stepped.x, std::sin(0.6), 1e-9);
  EXPECT_NEAR(stepped.z, std::cos(0.6), 1e-9);
  EXPECT_NEAR(towards_walls({{0, 0, 9}, {-0.7, 0, 0}, {0.3, 0, 0}}, view).x, -std::sin(0.6), 1e-9);
  // Half walls (no one face), or faces that all look at the view askew: left as it is.
  EXPECT_EQ(towards_walls({{0, 0, 1}, {1, 0, 0}}, view), view);
  EXPECT_EQ(towards_walls({{0, 0.6, 0.8}, {0, -0.6, 0.8}, {0.1, 0, 0}}, view), view);
}

}  // namespace
}  // namespace fracref
