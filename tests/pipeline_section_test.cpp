// pipeline/section_preview: the section through the material, with the coarse and refined cuts.
#include <gtest/gtest.h>

#include "pipeline/section_preview.hpp"
#include "pipeline/surface_preview.hpp"
#include "refine_test_support.hpp"

namespace fracref {
namespace {

FractureSurface sheet_at(float z) { return test::sheet(4, z); }

// ζ = 1 on [-0.1, 1.1]³ but for a weak slab (0) whose nodes lie at z = 0.6 and 0.65.
Grid3 slab_field() {
  return test::grid_of(glm::dvec3(-0.1), 0.05, 25, [](const glm::dvec3& p) { return p.z > 0.59 && p.z < 0.66 ? 0.0 : 1.0; });
}

// A linear colour as the previews write it (sRGB, 8 bits).
glm::ivec3 encoded(const glm::vec3& c) {
  Image one{1, 1, std::vector<std::uint8_t>(3)};
  set_pixel(one, 0, 0, c);
  return {one.rgb[0], one.rgb[1], one.rgb[2]};
}

glm::ivec3 pixel(const Image& img, int x, int y) {
  const std::uint8_t* p = &img.rgb[3 * (std::size_t(y) * img.width + x)];
  return {p[0], p[1], p[2]};
}

TEST(SectionSegments, ATriangleAcrossThePlaneGivesOneSegmentOnIt) {
  const std::vector<glm::dvec3> p = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  const auto cut = section_segments(p, {{0, 1, 2}}, {0, 1.0});
  ASSERT_EQ(cut.size(), 1u);
  for (const glm::dvec3& e : cut[0]) EXPECT_DOUBLE_EQ(e.x, 1.0);
  EXPECT_DOUBLE_EQ(std::max(cut[0][0].y, cut[0][1].y), 1.0);
  EXPECT_DOUBLE_EQ(std::min(cut[0][0].y, cut[0][1].y), 0.0);
  EXPECT_TRUE(section_segments(p, {{0, 1, 2}}, {0, 3.0}).empty());
  EXPECT_TRUE(section_segments(p, {{0, 1, 2}}, {2, 0.5}).empty());  // the triangle lies in z = 0
}

TEST(BestSection, CutsAcrossASheetNotAlongIt) {
  const SectionPlane plane = best_section(sheet_at(0.5f), glm::dvec3(0.0), glm::dvec3(1.0));
  EXPECT_EQ(plane.axis, 0);  // x and y cut it alike: the lower axis, at the middle
  EXPECT_DOUBLE_EQ(plane.at, 0.5);
  // A sheet standing in x = 0.3 is cut by y and z planes only.
  FractureSurface standing = sheet_at(0.3f);
  for (glm::vec4& p : standing.positions) p = glm::vec4(p.z, p.x, p.y, 1.0f);
  EXPECT_EQ(best_section(standing, glm::dvec3(0.0), glm::dvec3(1.0)).axis, 1);
}

// In the section x = 0.5 (y right, z up) of the unit cube, 400 × 300 pixels: the cube is 220
// pixels wide, from (90, 40) to (310, 260). The refined cut at z = 0.62 lies in the weak slab and
// is green; the coarse cut at z = 0.5 is dashed black; ζ = 1 is the ramp's pale yellow, the slab
// its dark purple, with white where ζ crosses the threshold; outside the cube, the background.
TEST(PreviewSection, ShowsTheCutsOnTheMaterial) {
  const Grid3 zeta = slab_field();
  const Image img = preview_section(zeta, 0.5, test::unit_cube(), sheet_at(0.5f), sheet_at(0.62f), 400, 300);
  ASSERT_EQ(img.width, 400);
  ASSERT_EQ(img.height, 300);
  const auto row = [](double z) { return int(260.0 - z * 220.0); };
  EXPECT_EQ(pixel(img, 200, row(0.62)), encoded(glm::vec3(0.15f, 0.95f, 0.25f)));  // green
  int black = 0;
  for (int x = 100; x < 300; ++x) black += pixel(img, x, row(0.5)) == glm::ivec3(0);
  EXPECT_GT(black, 50);   // dashed: about half the row
  EXPECT_LT(black, 150);
  const glm::ivec3 strong = pixel(img, 200, row(0.3)), weak = pixel(img, 150, row(0.64));
  EXPECT_GT(strong.x + strong.y + strong.z, 600);  // pale yellow
  EXPECT_LT(2 * (weak.x + weak.y + weak.z), strong.x + strong.y + strong.z);  // dark purple
  // Both exactly the ramp's colours, as preview_surface.png would draw them.
  const StrengthRamp ramp(zeta);
  EXPECT_EQ(strong, encoded(ramp.at({0.5, 0.5, 0.3})));
  EXPECT_EQ(weak, encoded(ramp.at({0.5, 0.5, 0.64})));
  int white = 0;
  for (int y = row(0.75); y < row(0.5); ++y) white += pixel(img, 150, y) == glm::ivec3(255);
  EXPECT_GE(white, 2);  // the slab's two edges
  EXPECT_EQ(pixel(img, 20, 150), encoded(RenderOptions{}.background));  // background, outside the cube
  EXPECT_EQ(pixel(img, 380, 20), encoded(RenderOptions{}.background));
}

}  // namespace
}  // namespace fracref
