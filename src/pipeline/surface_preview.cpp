#include "pipeline/surface_preview.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "field/field_sampler.hpp"

namespace fracref {

namespace {

glm::vec3 strength_color(double t) {
  static const std::array<glm::vec3, 5> stops = {glm::vec3(0.16f, 0.05f, 0.30f), glm::vec3(0.55f, 0.10f, 0.45f),
                                                 glm::vec3(0.90f, 0.30f, 0.20f), glm::vec3(0.98f, 0.65f, 0.20f),
                                                 glm::vec3(0.99f, 0.95f, 0.70f)};
  const double x = std::clamp(t, 0.0, 1.0) * double(stops.size() - 1);
  const std::size_t i = std::min<std::size_t>(std::size_t(x), stops.size() - 2);
  const float f = float(x - double(i));
  return stops[i] * (1.0f - f) + stops[i + 1] * f;
}

}  // namespace

glm::vec3 piece_color(int piece) {
  static const glm::vec3 palette[] = {{0.90f, 0.35f, 0.30f}, {0.30f, 0.60f, 0.90f}, {0.40f, 0.80f, 0.40f},
                                      {0.95f, 0.75f, 0.25f}, {0.65f, 0.45f, 0.85f}, {0.30f, 0.80f, 0.80f},
                                      {0.90f, 0.50f, 0.70f}, {0.60f, 0.60f, 0.35f}};
  return palette[std::size_t(piece) % 8];
}

StrengthRamp::StrengthRamp(const Grid3& zeta) : zeta_(zeta) {
  if (zeta.values.empty()) return;
  const auto [lo, hi] = std::minmax_element(zeta.values.begin(), zeta.values.end());
  lo_ = double(*lo), range_ = double(*hi) - double(*lo);
}

glm::vec3 StrengthRamp::at(const glm::dvec3& p) const {
  return strength_color(range_ > 0.0 ? (sample_trilinear(zeta_, p) - lo_) / range_ : 0.5);
}

namespace {

// Of the candidate directions, the one along which the surface's projected area is largest
// (faces seen from both sides count once each); the first on ties.
glm::dvec3 widest_view(const PreviewMesh& m) {
  const glm::dvec3 candidates[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {1, 1, -1}};
  glm::dvec3 best = candidates[0];
  double best_area = -1.0;
  for (const glm::dvec3& c : candidates) {
    const glm::dvec3 v = glm::normalize(c);
    double area = 0.0;
    for (const auto& t : m.triangles)
      area += std::abs(glm::dot(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]), v));
    if (area > best_area) best_area = area, best = v;
  }
  return best;
}

}  // namespace

Image preview_strength_surface(const FractureSurface& s, const Grid3& zeta, int width, int height) {
  PreviewMesh m;
  const StrengthRamp ramp(zeta);
  for (const glm::vec4& p : s.positions) m.positions.push_back(glm::dvec3(glm::vec3(p)));
  for (const glm::uvec4& f : s.faces) {
    m.triangles.push_back({f.x, f.y, f.z});
    m.triangle_colors.push_back(ramp.at((m.positions[f.x] + m.positions[f.y] + m.positions[f.z]) / 3.0));
  }
  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  const glm::dvec3 view = widest_view(m);
  ro.view_direction = -view;
  ro.up = std::abs(view.y) > 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  ro.light_direction = glm::normalize(-view + glm::dvec3(0.3, -0.5, 0.2));
  return render_preview({m}, ro);
}

}  // namespace fracref
