#include "pipeline/section_preview.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "field/field_sampler.hpp"
#include "pipeline/surface_preview.hpp"

namespace fracref {
namespace {

using Segment = std::array<glm::dvec3, 2>;

// S's positions in double and its faces as triangles, for section_segments.
struct Soup {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  explicit Soup(const FractureSurface& s) : positions(double_positions(s)) {
    triangles.reserve(s.faces.size());
    for (const glm::uvec4& f : s.faces) triangles.push_back({f.x, f.y, f.z});
  }
  std::vector<Segment> section(const SectionPlane& plane) const { return section_segments(positions, triangles, plane); }
};

double total_length(const std::vector<Segment>& segments) {
  double sum = 0.0;
  for (const Segment& g : segments) sum += glm::distance(g[0], g[1]);
  return sum;
}

// Of the 15 axis-aligned planes (35% to 65% of the box along each axis), the one where the soup's
// section is longest; the first on ties, nearest the middle.
SectionPlane longest_section(const Soup& soup, const glm::dvec3& lo, const glm::dvec3& hi) {
  static constexpr double kFractions[] = {0.5, 0.425, 0.575, 0.35, 0.65};  // nearest the middle first
  SectionPlane best{0, 0.5 * (lo.x + hi.x)};
  double longest = -1.0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double f : kFractions) {
      const SectionPlane plane{axis, lo[axis] + f * (hi[axis] - lo[axis])};
      const double length = total_length(soup.section(plane));
      if (length > longest) longest = length, best = plane;
    }
  return best;
}

// The picture's frame: the plane's other two axes (u right, v up) fitted to the pixels.
struct Frame {
  int u = 1, v = 2, width = 0, height = 0;
  double scale = 1.0;
  glm::dvec2 origin{0.0};  // (u, v) at the picture's bottom-left corner
  glm::dvec2 pixel(const glm::dvec3& p) const {
    return {(p[u] - origin.x) * scale, double(height) - (p[v] - origin.y) * scale};
  }
  glm::dvec2 point(double x, double y) const { return {origin.x + x / scale, origin.y + (double(height) - y) / scale}; }
};

Frame fit_frame(const SectionPlane& plane, const glm::dvec3& lo, const glm::dvec3& hi, int width, int height) {
  constexpr double kMargin = 40.0;
  Frame f;
  f.u = plane.axis == 0 ? 1 : 0, f.v = plane.axis == 2 ? 1 : 2;
  f.width = width, f.height = height;
  const double du = std::max(hi[f.u] - lo[f.u], 1e-12), dv = std::max(hi[f.v] - lo[f.v], 1e-12);
  f.scale = std::min((width - 2.0 * kMargin) / du, (height - 2.0 * kMargin) / dv);
  f.origin = glm::dvec2(lo[f.u] - 0.5 * (width / f.scale - du), lo[f.v] - 0.5 * (height / f.scale - dv));
  return f;
}

// Per pixel row, whether each pixel's centre is inside the exterior: the crossings of the row
// with the exterior's section, paired left to right (the section of a closed surface is closed
// loops).
std::vector<char> inside_mask(const std::vector<Segment>& outline, const Frame& f) {
  std::vector<char> inside(std::size_t(f.width) * f.height, 0);
  std::vector<double> xs;
  for (int y = 0; y < f.height; ++y) {
    const double row = y + 0.5;
    xs.clear();
    for (const Segment& g : outline) {
      const glm::dvec2 a = f.pixel(g[0]), b = f.pixel(g[1]);
      if ((a.y <= row) != (b.y <= row)) xs.push_back(a.x + (row - a.y) * (b.x - a.x) / (b.y - a.y));
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
      for (int x = std::max(0, int(std::ceil(xs[k] - 0.5))); x < f.width && x + 0.5 <= xs[k + 1]; ++x)
        inside[std::size_t(y) * f.width + x] = 1;
  }
  return inside;
}

// Each segment stamped with a square of `half` pixels either side; dashed: only where the pixel's
// 8-pixel checkerboard square is dark, so a line of any direction shows dashes.
void draw_segments(Image& img, const Frame& f, const std::vector<Segment>& segments, const glm::vec3& colour, int half,
                   bool dashed) {
  for (const Segment& g : segments) {
    const glm::dvec2 a = f.pixel(g[0]), b = f.pixel(g[1]);
    const int steps = std::max(1, int(std::ceil(2.0 * glm::distance(a, b))));
    for (int k = 0; k <= steps; ++k) {
      const glm::dvec2 p = a + (b - a) * (double(k) / steps);
      const int cx = int(std::floor(p.x)), cy = int(std::floor(p.y));
      if (dashed && ((int(std::floor(p.x / 8.0)) + int(std::floor(p.y / 8.0))) & 1)) continue;
      for (int dy = -half; dy <= half; ++dy)
        for (int dx = -half; dx <= half; ++dx) set_pixel(img, cx + dx, cy + dy, colour);
    }
  }
}

// ζ's ramp inside the exterior, the background outside it, and white where ζ crosses the threshold
// between a pixel and its right or lower neighbour inside.
void paint_field(Image& img, const Frame& f, const SectionPlane& plane, const Grid3& zeta, double threshold,
                 const std::vector<char>& inside) {
  const StrengthRamp ramp(zeta);
  const glm::vec3 background = RenderOptions{}.background;
  std::vector<char> weak(inside.size(), 0);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const glm::dvec2 uv = f.point(x + 0.5, y + 0.5);
      glm::dvec3 p(plane.at);
      p[f.u] = uv.x, p[f.v] = uv.y;
      const std::size_t i = std::size_t(y) * f.width + x;
      if (!inside[i]) {
        set_pixel(img, x, y, background);
        continue;
      }
      weak[i] = sample_trilinear(zeta, p) < threshold;
      set_pixel(img, x, y, ramp.at(p));
    }
  for (int y = 0; y + 1 < f.height; ++y)
    for (int x = 0; x + 1 < f.width; ++x) {
      const std::size_t i = std::size_t(y) * f.width + x;
      if (inside[i] && (weak[i] != weak[i + 1] || weak[i] != weak[i + f.width])) set_pixel(img, x, y, glm::vec3(1.0f));
    }
}

}  // namespace

std::vector<Segment> section_segments(const std::vector<glm::dvec3>& positions,
                                      const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                      const SectionPlane& plane) {
  std::vector<Segment> out;
  for (const auto& t : triangles) {
    glm::dvec3 ends[2];
    int n = 0;
    for (int k = 0; k < 3 && n < 2; ++k) {
      const glm::dvec3 a = positions[t[k]], b = positions[t[(k + 1) % 3]];
      const double da = a[plane.axis] - plane.at, db = b[plane.axis] - plane.at;
      if ((da >= 0.0) == (db >= 0.0)) continue;
      ends[n++] = a + (b - a) * (da / (da - db));
    }
    if (n == 2) out.push_back({ends[0], ends[1]});
  }
  return out;
}

SectionPlane best_section(const FractureSurface& s, const glm::dvec3& lo, const glm::dvec3& hi) {
  return longest_section(Soup(s), lo, hi);
}

Image preview_section(const Grid3& zeta, double weak_threshold, const MeshSoup& exterior, const FractureSurface& coarse,
                      const FractureSurface& refined, int width, int height) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : exterior.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const Soup refined_soup(refined);  // converted once: the plane's choice and the green line
  const SectionPlane plane = longest_section(refined_soup, lo, hi);
  const Frame f = fit_frame(plane, lo, hi, width, height);
  Image img{width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 3, 0)};
  const std::vector<Segment> outline = section_segments(exterior.positions, exterior.triangles, plane);
  paint_field(img, f, plane, zeta, weak_threshold, inside_mask(outline, f));
  draw_segments(img, f, outline, glm::vec3(0.35f), 0, false);
  draw_segments(img, f, Soup(coarse).section(plane), glm::vec3(0.0f), 1, true);
  draw_segments(img, f, refined_soup.section(plane), glm::vec3(0.15f, 0.95f, 0.25f), 1, false);
  return img;
}

}  // namespace fracref
