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

FractureColour fracture_colour(const std::array<Grid3, 3>* albedo, const StrengthRamp& ramp) {
  if (albedo)
    return [albedo](const glm::dvec3& p) {
      const glm::vec3 c(sample_trilinear((*albedo)[0], p), sample_trilinear((*albedo)[1], p), sample_trilinear((*albedo)[2], p));
      return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
    };
  return [&ramp](const glm::dvec3& p) { return ramp.at(p); };
}

glm::dvec3 towards_walls(const std::vector<glm::dvec3>& normals, const glm::dvec3& view) {
  constexpr double kFewest = 0.05, kMost = 0.3, kFacing = 0.75, kTurn = 0.6;
  glm::dmat3 scatter(0.0);  // of the walls' unit directions across the view, by area
  double walls = 0.0, total = 0.0, facing_view = 0.0, largest = 0.0;
  glm::dvec3 d(0.0);
  for (const glm::dvec3& n : normals) {
    const double area = glm::length(n);
    const glm::dvec3 across = n - glm::dot(n, view) * view;
    total += area, facing_view += std::abs(glm::dot(n, view));
    if (!(std::abs(glm::dot(n, view)) < 0.5 * area) || !(glm::length(across) > 0.0)) continue;
    const glm::dvec3 u = glm::normalize(across);
    scatter += area * glm::outerProduct(u, u), walls += area;
    if (area > largest) largest = area, d = u;
  }
  // No steps, or no one face that the view looks at (a surface of many directions, seen from
  // the best compromise already).
  if (!(walls > kFewest * total) || walls > kMost * total || facing_view < kFacing * total) return view;
  // The walls' main direction, by power iteration from the largest wall's (which is not
  // orthogonal to it: its own term alone keeps it off).
  for (int i = 0; i < 32; ++i) d = glm::normalize(scatter * d);
  double facing = 0.0;  // wall area that faces d less that facing -d
  for (const glm::dvec3& n : normals) {
    const double area = glm::length(n);
    if (std::abs(glm::dot(n, view)) < 0.5 * area) facing += glm::dot(n, d) > 0.0 ? area : -area;
  }
  if (facing < 0.0) d = -d;
  return glm::normalize(std::cos(kTurn) * view + std::sin(kTurn) * d);
}

namespace {

// The camera's up hint for a view along `view` (render_preview needs one not along the view).
glm::dvec3 up_for(const glm::dvec3& view) {
  return std::abs(view.y) > 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
}

// How well a view along `view` shows the surface: the pixels it covers in a picture a tenth of
// width × height, fitted to the frame as render_preview fits it, times the fraction of its area
// (`normals` as long as their faces' areas) that the view does not see edge-on. Its projected
// area would count sheets behind one another again and again; the pixels alone would pick a
// view along a wall, where its head joints fill a column and its bed joints are lines.
double view_score(const PreviewMesh& shape, const std::vector<glm::dvec3>& normals, const glm::dvec3& view, int width,
                  int height) {
  constexpr double kEdgeOn = 0.3;  // |cos| of the angle between a face's normal and the view
  RenderOptions ro;
  ro.width = std::max(1, width / 10), ro.height = std::max(1, height / 10), ro.supersample = 1;
  ro.view_direction = -view, ro.up = up_for(view);
  ro.background = glm::vec3(0.0f);  // the shading lights every face to at least 0.28
  const Image image = render_preview({shape}, ro);
  std::size_t covered = 0;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) covered += (image.rgb[i] | image.rgb[i + 1] | image.rgb[i + 2]) != 0;
  double seen = 0.0, total = 0.0;
  for (const glm::dvec3& n : normals) {
    const double area = glm::length(n);
    total += area;
    if (std::abs(glm::dot(n, view)) > kEdgeOn * area) seen += area;
  }
  return total > 0.0 ? double(covered) * seen / total : 0.0;
}

// Of the candidate directions, the one with the best view_score; the first on ties.
glm::dvec3 best_view(const PreviewMesh& m, const std::vector<glm::dvec3>& normals, int width, int height) {
  PreviewMesh shape;  // its outline only: flat, one colour
  shape.positions = m.positions, shape.triangles = m.triangles;
  shape.triangle_colors.assign(m.triangles.size(), glm::vec3(1.0f));
  const glm::dvec3 candidates[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {1, 1, -1}};
  glm::dvec3 best = candidates[0];
  double best_score = -1.0;
  for (const glm::dvec3& c : candidates) {
    const glm::dvec3 v = glm::normalize(c);
    const double score = view_score(shape, normals, v, width, height);
    if (score > best_score) best_score = score, best = v;
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
  smooth_corner_normals(m, kPreviewCrease);
  m.paint = [&m, &ramp](std::size_t f, const glm::dvec3& b) {
    const auto& t = m.triangles[f];
    return ramp.at(b.x * m.positions[t[0]] + b.y * m.positions[t[1]] + b.z * m.positions[t[2]]);
  };
  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  std::vector<glm::dvec3> normals;
  for (const auto& t : m.triangles)
    normals.push_back(0.5 * glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
  const glm::dvec3 view = towards_walls(normals, best_view(m, normals, width, height));
  ro.view_direction = -view;
  ro.up = up_for(view);
  ro.light_direction = glm::normalize(-view + glm::dvec3(0.3, -0.5, 0.2));
  return render_preview({m}, ro);
}

}  // namespace fracref
