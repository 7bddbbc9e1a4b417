// The preview rasterizer's smooth lighting (corner normals blended across a gentle bend, kept
// apart across a crease or between groups) and its per-pixel paint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "preview/raster.hpp"

namespace fracref {
namespace {

// Two triangles sharing edge (0, 1) along the y axis; the second is bent `degrees` out of the
// first's plane (z = 0). When `flip`, the second is wound the other way round.
PreviewMesh hinge(double degrees, bool flip = false) {
  const double a = degrees * 3.14159265358979323846 / 180.0;
  PreviewMesh m;
  m.positions = {{0, 0, 0}, {0, 1, 0}, {-1, 0.5, 0}, {std::cos(a), 0.5, std::sin(a)}};
  m.triangles = {{0, 1, 2}, flip ? std::array<std::uint32_t, 3>{0, 1, 3} : std::array<std::uint32_t, 3>{0, 3, 1}};
  m.triangle_colors.assign(2, glm::vec3(0.8f));
  return m;
}

glm::dvec3 unit(const glm::vec3& v) { return glm::normalize(glm::dvec3(v)); }

TEST(SmoothCornerNormals, AGentleBendIsBlendedAtItsSharedCornersOnly) {
  PreviewMesh m = hinge(20.0);
  smooth_corner_normals(m, 45.0);
  ASSERT_EQ(m.corner_normals.size(), 6u);
  // Corners 0 and 1 of triangle 0 are on the hinge: both triangles' normals, so a normal tilted
  // 10 degrees from each; corner 2 is the first triangle's alone.
  const glm::dvec3 n0(0, 0, 1);  // (0,1,0) × (−1,0.5,0)
  EXPECT_NEAR(glm::dot(unit(m.corner_normals[0]), n0), std::cos(10.0 * 3.14159265358979323846 / 180.0), 1e-6);
  EXPECT_NEAR(glm::dot(unit(m.corner_normals[2]), n0), 1.0, 1e-12);
  // The second triangle's hinge corners have the same normal as the first's.
  EXPECT_NEAR(glm::dot(unit(m.corner_normals[0]), unit(m.corner_normals[3])), 1.0, 1e-6);
}

TEST(SmoothCornerNormals, ACreaseAGroupLineAndAnOppositeWindingAreHandled) {
  PreviewMesh crease = hinge(60.0);
  smooth_corner_normals(crease, 45.0);
  EXPECT_NEAR(glm::dot(unit(crease.corner_normals[0]), glm::dvec3(0, 0, 1)), 1.0, 1e-12);

  PreviewMesh grouped = hinge(20.0);
  smooth_corner_normals(grouped, 45.0, {0, 1});
  EXPECT_NEAR(glm::dot(unit(grouped.corner_normals[0]), glm::dvec3(0, 0, 1)), 1.0, 1e-12);

  // Wound the other way, the second triangle's normal is turned round before it is added: the
  // blend is the same as for a consistent winding, on each triangle's own side.
  PreviewMesh flipped = hinge(20.0, true), same = hinge(20.0);
  smooth_corner_normals(flipped, 45.0);
  smooth_corner_normals(same, 45.0);
  EXPECT_NEAR(glm::dot(unit(flipped.corner_normals[0]), unit(same.corner_normals[0])), 1.0, 1e-6);
  EXPECT_NEAR(glm::dot(unit(flipped.corner_normals[3]), unit(same.corner_normals[3])), -1.0, 1e-6);
}

// The largest step in brightness (the red channel) between two covered neighbours in a row.
int largest_step(const Image& im, const glm::vec3& background) {
  const int bg = int(std::lround(255.0 * std::pow(background.r, 1.0 / 2.2)));
  int most = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 1; x < im.width; ++x) {
      const int a = im.rgb[3 * (std::size_t(y) * im.width + x - 1)], b = im.rgb[3 * (std::size_t(y) * im.width + x)];
      if (std::abs(a - bg) < 12 || std::abs(b - bg) < 12) continue;  // at the outline
      most = std::max(most, std::abs(a - b));
    }
  return most;
}

TEST(RenderPreview, SmoothNormalsLightABendWithoutAStepAtItsEdge) {
  RenderOptions o;
  o.width = 200, o.height = 200, o.supersample = 1;
  o.view_direction = {0.0, 0.0, -1.0};
  o.light_direction = {0.6, 0.0, -0.8};
  o.background = glm::vec3(0.0f);
  PreviewMesh flat = hinge(30.0), smooth = hinge(30.0);
  smooth_corner_normals(smooth, 45.0);
  const int flat_step = largest_step(render_preview({flat}, o), o.background);
  const int smooth_step = largest_step(render_preview({smooth}, o), o.background);
  EXPECT_GT(flat_step, 10);  // the hinge, lit differently on its two sides
  EXPECT_LT(smooth_step, flat_step / 4);
}

TEST(RenderPreview, PaintColoursEachPixelFromItsBarycentricCoordinates) {
  PreviewMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  m.triangle_colors = {glm::vec3(0.5f)};
  m.paint = [](std::size_t, const glm::dvec3& b) { return glm::vec3(float(b.x), float(b.y), float(b.z)); };
  RenderOptions o;
  o.width = 120, o.height = 120, o.supersample = 1;
  o.view_direction = {0.0, 0.0, -1.0};
  o.light_direction = {0.0, 0.0, -1.0};
  o.background = glm::vec3(1.0f);
  const Image im = render_preview({m}, o);
  std::set<int> reds;
  std::size_t red_corner = 0, green_corner = 0;
  for (std::size_t i = 0; i + 2 < im.rgb.size(); i += 3) {
    const int r = im.rgb[i], g = im.rgb[i + 1], b = im.rgb[i + 2];
    if (r == 255 && g == 255 && b == 255) continue;
    reds.insert(r);
    red_corner += r > 200 && g < 60 && b < 60;
    green_corner += g > 200 && r < 60 && b < 60;
  }
  EXPECT_GT(reds.size(), 50u);  // a ramp, not one colour
  EXPECT_GT(red_corner, 0u);
  EXPECT_GT(green_corner, 0u);
}

}  // namespace
}  // namespace fracref
