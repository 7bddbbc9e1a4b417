// preview.png shows every piece's fracture faces: a box cut in two by a flat sheet, whose two
// fracture faces look in opposite directions (no one camera on the pieces in place sees both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

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

TEST(PiecesPreview, TheMaterialsOwnColoursPaintTheFractureFaces) {
  const MeshSoup b = box({0, 0, -1}, {3, 3, 1}, 1);
  const PieceSet set = build_pieces(example_sheet(4), b);
  Grid3 zeta;
  zeta.dims = {2, 2, 2}, zeta.origin = glm::dvec3(-1.0), zeta.cell = 10.0;
  zeta.values.assign(8, 0.5f);
  std::array<Grid3, 3> green{zeta, zeta, zeta};  // a material of one colour, (0, 0.8, 0)
  green[0].values.assign(8, 0.0f), green[1].values.assign(8, 0.8f), green[2].values.assign(8, 0.0f);
  const Image im = preview_pieces(set, &zeta, &green);
  std::size_t greens = 0;
  for (std::size_t i = 0; i + 2 < im.rgb.size(); i += 3) greens += im.rgb[i + 1] > im.rgb[i] + 60 && im.rgb[i + 1] > im.rgb[i + 2] + 60;
  EXPECT_GT(greens, std::size_t(im.width) * std::size_t(im.height) / 10);
  // Without it, ζ's ramp: no green.
  const Image ramp = preview_pieces(set, &zeta);
  std::size_t ramp_greens = 0;
  for (std::size_t i = 0; i + 2 < ramp.rgb.size(); i += 3) ramp_greens += ramp.rgb[i + 1] > ramp.rgb[i] + 60 && ramp.rgb[i + 1] > ramp.rgb[i + 2] + 60;
  EXPECT_EQ(ramp_greens, 0u);
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

// A break through a long, thin wall (6 × 2 × 0.2): treads along the wall's length and risers
// between them, each across the wall's thickness. Seen from above, where its projected area is
// largest, it would be a strip across the picture; seen askew, its steps fill the picture.
FractureSurface wall_staircase() {
  std::vector<glm::vec4> p;
  std::vector<glm::uvec4> f;
  auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const std::uint32_t n = std::uint32_t(p.size());
    for (const glm::vec3& q : {a, b, c, d}) p.push_back(glm::vec4(q, 1.0f));
    f.push_back({n, n + 1, n + 2, 0}), f.push_back({n, n + 2, n + 3, 0});
  };
  for (int k = 0; k < 12; ++k) {
    const float x = float(k % 6) + (k < 6 ? 0.0f : 2.5f), y = 0.3f * float(k % 6);
    quad({x, y, 0.0f}, {x + 1.0f, y, 0.0f}, {x + 1.0f, y, 0.2f}, {x, y, 0.2f});
    if (k % 6 < 5) quad({x + 1.0f, y, 0.0f}, {x + 1.0f, y + 0.3f, 0.0f}, {x + 1.0f, y + 0.3f, 0.2f}, {x + 1.0f, y, 0.2f});
  }
  return make_fracture_surface(p, f, std::vector<glm::ivec2>(f.size(), glm::ivec2(0, 1)), 2);
}

TEST(SurfacePreview, ALongThinBreakIsSeenWithItsTreadsAndItsRisers) {
  Grid3 zeta;  // constant: every face has the same colour, and its shading tells treads from risers
  zeta.dims = {2, 2, 2}, zeta.origin = glm::dvec3(-1.0), zeta.cell = 10.0;
  zeta.values.assign(8, 0.5f);
  const Image im = preview_strength_surface(wall_staircase(), zeta);
  ASSERT_EQ(im.width, 1600);
  std::map<std::uint32_t, std::size_t> colours;  // of the pixels off the background (light grey)
  for (std::size_t i = 0; i + 2 < im.rgb.size(); i += 3)
    if (im.rgb[i + 2] < 200) ++colours[std::uint32_t(im.rgb[i]) << 16 | std::uint32_t(im.rgb[i + 1]) << 8 | im.rgb[i + 2]];
  std::vector<std::size_t> counts;
  for (const auto& [c, n] : colours) counts.push_back(n);
  std::sort(counts.rbegin(), counts.rend());
  ASSERT_GE(counts.size(), 2u);
  // Seen along the wall (most pixels) the treads would be lines, seen from above (the largest
  // projected area) the risers: the second shade would be only the edges' blends.
  const std::size_t pixels = std::size_t(im.width) * std::size_t(im.height);
  EXPECT_GT(counts[0], pixels / 50);
  EXPECT_GT(counts[1], pixels / 200);
}

}  // namespace
}  // namespace fracref
