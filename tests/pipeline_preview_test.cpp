// preview.png shows every piece's fracture faces: a box cut in two by a flat sheet, whose two
// fracture faces look in opposite directions (no one camera on the pieces in place sees both).
#include <gtest/gtest.h>

#include "pieces_test_support.hpp"
#include "pipeline/job_outputs.hpp"
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

}  // namespace
}  // namespace fracref
