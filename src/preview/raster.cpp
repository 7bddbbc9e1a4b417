#include "preview/raster.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

struct Camera {
  glm::dvec3 right, up, forward, center;
  double scale;  // pixels per scene unit
  int width, height;

  glm::dvec3 project(const glm::dvec3& p) const {
    glm::dvec3 d = p - center;
    return {width * 0.5 + glm::dot(d, right) * scale, height * 0.5 - glm::dot(d, up) * scale,
            glm::dot(d, forward)};
  }
};

Camera fit_camera(const std::vector<PreviewMesh>& meshes, const RenderOptions& o, int w, int h) {
  Camera c{};
  c.forward = glm::normalize(o.view_direction);
  c.right = glm::normalize(glm::cross(c.forward, o.up));
  c.up = glm::cross(c.right, c.forward);
  c.width = w;
  c.height = h;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& m : meshes)
    for (const auto& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (lo.x > hi.x) lo = hi = glm::dvec3(0.0);
  c.center = 0.5 * (lo + hi);
  double extent_x = 0.0, extent_y = 0.0;
  for (const auto& m : meshes)
    for (const auto& p : m.positions) {
      extent_x = std::max(extent_x, std::abs(glm::dot(p - c.center, c.right)));
      extent_y = std::max(extent_y, std::abs(glm::dot(p - c.center, c.up)));
    }
  double sx = extent_x > 0 ? 0.45 * w / extent_x : 1.0;
  double sy = extent_y > 0 ? 0.45 * h / extent_y : 1.0;
  c.scale = std::min(sx, sy);
  return c;
}

struct Target {
  int w, h;
  std::vector<float> depth;
  std::vector<glm::vec3> color;
};

void draw_triangle(Target& t, const glm::dvec3 s[3], const glm::vec3& rgb) {
  double minx = std::floor(std::min({s[0].x, s[1].x, s[2].x})), maxx = std::ceil(std::max({s[0].x, s[1].x, s[2].x}));
  double miny = std::floor(std::min({s[0].y, s[1].y, s[2].y})), maxy = std::ceil(std::max({s[0].y, s[1].y, s[2].y}));
  int x0 = std::max(0, int(minx)), x1 = std::min(t.w - 1, int(maxx));
  int y0 = std::max(0, int(miny)), y1 = std::min(t.h - 1, int(maxy));
  double area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
  if (std::abs(area) < 1e-12) return;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      double px = x + 0.5, py = y + 0.5;
      double w0 = (s[1].x - px) * (s[2].y - py) - (s[2].x - px) * (s[1].y - py);
      double w1 = (s[2].x - px) * (s[0].y - py) - (s[0].x - px) * (s[2].y - py);
      double w2 = area - w0 - w1;
      if (area < 0) w0 = -w0, w1 = -w1, w2 = -w2;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      double a = std::abs(area);
      float z = float((w0 * s[0].z + w1 * s[1].z + w2 * s[2].z) / a);
      std::size_t i = std::size_t(y) * t.w + x;
      if (z < t.depth[i]) t.depth[i] = z, t.color[i] = rgb;
    }
}

glm::vec3 shade(const glm::dvec3 p[3], const glm::vec3& base, const RenderOptions& o) {
  glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
  double len = glm::length(n);
  if (len == 0.0) return base;
  n /= len;
  glm::dvec3 l = -glm::normalize(o.light_direction);
  double diffuse = std::abs(glm::dot(n, l));  // two-sided
  double rim = std::abs(glm::dot(n, glm::normalize(o.view_direction)));
  float k = float(0.28 + 0.62 * diffuse + 0.10 * rim);
  return glm::min(base * k, glm::vec3(1.0f));
}

// sRGB encoding through a table: the per-pixel pow() dominated the preview's time.
std::uint8_t to_srgb8(float linear) {
  static const std::vector<std::uint8_t> table = [] {
    std::vector<std::uint8_t> t(4097);
    for (int i = 0; i <= 4096; ++i) {
      float c = float(i) / 4096.0f;
      float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
      t[i] = std::uint8_t(std::lround(s * 255.0f));
    }
    return t;
  }();
  return table[std::size_t(std::clamp(linear, 0.0f, 1.0f) * 4096.0f + 0.5f)];
}

Image resolve(const Target& t, int ss, const glm::vec3& background, int w, int h) {
  Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * h * 3)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 sum(0.0f);
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
          std::size_t k = std::size_t(y * ss + j) * t.w + (x * ss + i);
          sum += t.depth[k] == std::numeric_limits<float>::max() ? background : t.color[k];
        }
      sum /= float(ss * ss);
      std::size_t o = (std::size_t(y) * w + x) * 3;
      img.rgb[o] = to_srgb8(sum.r), img.rgb[o + 1] = to_srgb8(sum.g), img.rgb[o + 2] = to_srgb8(sum.b);
    }
  return img;
}

}  // namespace

Image render_preview(const std::vector<PreviewMesh>& meshes, const RenderOptions& o) {
  int ss = std::max(1, o.supersample);
  int W = o.width * ss, H = o.height * ss;
  Camera cam = fit_camera(meshes, o, W, H);
  Target t{W, H, std::vector<float>(std::size_t(W) * H, std::numeric_limits<float>::max()),
           std::vector<glm::vec3>(std::size_t(W) * H)};
  for (const auto& m : meshes)
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
      glm::dvec3 p[3], s[3];
      for (int k = 0; k < 3; ++k) p[k] = m.positions[m.triangles[f][k]], s[k] = cam.project(p[k]);
      draw_triangle(t, s, shade(p, m.triangle_colors[f], o));
    }
  return resolve(t, ss, o.background, o.width, o.height);
}

Image contact_sheet(const std::vector<Image>& images, int columns) {
  if (images.empty()) return {};
  int w = images[0].width, h = images[0].height;
  int cols = std::max(1, std::min<int>(columns, int(images.size())));
  int rows = int((images.size() + cols - 1) / cols);
  Image sheet{w * cols, h * rows, std::vector<std::uint8_t>(std::size_t(w) * cols * h * rows * 3, 255)};
  for (std::size_t i = 0; i < images.size(); ++i) {
    int ox = int(i % cols) * w, oy = int(i / cols) * h;
    for (int y = 0; y < h; ++y)
      std::copy_n(images[i].rgb.begin() + std::size_t(y) * w * 3, std::size_t(w) * 3,
                  sheet.rgb.begin() + (std::size_t(oy + y) * sheet.width + ox) * 3);
  }
  return sheet;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  png.flags = PNG_IMAGE_FLAG_FAST;  // a preview: speed over the last percent of size
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgb.data(), 0, nullptr))
    throw RunError(path.string() + ": PNG encoding failed: " + png.message);
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgb.data(), 0, nullptr))
    throw RunError(path.string() + ": PNG encoding failed: " + png.message);
  bytes.resize(size);
  write_file_atomic(path, bytes);
}

}  // namespace fracref
