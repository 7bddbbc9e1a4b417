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

// One triangle's corners on screen (x, y in pixels, z depth), with what is blended across it.
struct Corners {
  glm::dvec3 screen[3];
  glm::vec3 color;  // without a paint function
  glm::dvec3 normal[3];
  const PreviewMesh* mesh = nullptr;  // with a paint function, and the triangle to paint
  std::size_t triangle = 0;
};

glm::vec3 shade(glm::dvec3 n, const glm::vec3& base, const RenderOptions& o) {
  const double len = glm::length(n);
  if (!(len > 0.0)) return base;
  n /= len;
  const glm::dvec3 l = -glm::normalize(o.light_direction);
  const double diffuse = std::abs(glm::dot(n, l));  // two-sided
  const double rim = std::abs(glm::dot(n, glm::normalize(o.view_direction)));
  const float k = float(0.28 + 0.62 * diffuse + 0.10 * rim);
  return glm::min(base * k, glm::vec3(1.0f));
}

// A triangle with neither corner normals nor a paint function is shaded once; others per pixel.
void draw_triangle(Target& t, const Corners& c, bool blended, const RenderOptions& o) {
  const glm::dvec3* s = c.screen;
  const double minx = std::floor(std::min({s[0].x, s[1].x, s[2].x})), maxx = std::ceil(std::max({s[0].x, s[1].x, s[2].x}));
  const double miny = std::floor(std::min({s[0].y, s[1].y, s[2].y})), maxy = std::ceil(std::max({s[0].y, s[1].y, s[2].y}));
  const int x0 = std::max(0, int(minx)), x1 = std::min(t.w - 1, int(maxx));
  const int y0 = std::max(0, int(miny)), y1 = std::min(t.h - 1, int(maxy));
  const double area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
  if (std::abs(area) < 1e-12) return;
  const glm::vec3 flat = blended ? glm::vec3(0.0f) : shade(c.normal[0], c.color, o);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      double w0 = (s[1].x - px) * (s[2].y - py) - (s[2].x - px) * (s[1].y - py);
      double w1 = (s[2].x - px) * (s[0].y - py) - (s[0].x - px) * (s[2].y - py);
      double w2 = area - w0 - w1;
      if (area < 0) w0 = -w0, w1 = -w1, w2 = -w2;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      const double a = std::abs(area);
      const float z = float((w0 * s[0].z + w1 * s[1].z + w2 * s[2].z) / a);
      const std::size_t i = std::size_t(y) * t.w + x;
      if (!(z < t.depth[i])) continue;
      t.depth[i] = z;
      if (!blended) {
        t.color[i] = flat;
        continue;
      }
      const glm::dvec3 b(w0 / a, w1 / a, w2 / a);
      t.color[i] = shade(b.x * c.normal[0] + b.y * c.normal[1] + b.z * c.normal[2],
                         c.mesh ? c.mesh->paint(c.triangle, b) : c.color, o);
    }
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

void set_pixel(Image& image, int x, int y, const glm::vec3& c) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  const std::size_t o = (std::size_t(y) * image.width + x) * 3;
  image.rgb[o] = to_srgb8(c.r), image.rgb[o + 1] = to_srgb8(c.g), image.rgb[o + 2] = to_srgb8(c.b);
}

Image render_preview(const std::vector<PreviewMesh>& meshes, const RenderOptions& o) {
  int ss = std::max(1, o.supersample);
  int W = o.width * ss, H = o.height * ss;
  Camera cam = fit_camera(meshes, o, W, H);
  Target t{W, H, std::vector<float>(std::size_t(W) * H, std::numeric_limits<float>::max()),
           std::vector<glm::vec3>(std::size_t(W) * H)};
  for (const auto& m : meshes) {
    const bool normals = !m.corner_normals.empty();
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
      Corners c;
      if (m.paint) c.mesh = &m, c.triangle = f;
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = m.positions[m.triangles[f][k]], c.screen[k] = cam.project(p[k]);
      const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
      c.color = m.triangle_colors[f];
      for (int k = 0; k < 3; ++k) c.normal[k] = normals ? glm::dvec3(m.corner_normals[3 * f + k]) : n;
      draw_triangle(t, c, normals || m.paint, o);
    }
  }
  return resolve(t, ss, o.background, o.width, o.height);
}

void smooth_corner_normals(PreviewMesh& m, double crease_degrees, const std::vector<int>& groups) {
  const std::size_t n = m.triangles.size();
  std::vector<glm::dvec3> normal(n);  // as long as twice the area
  for (std::size_t f = 0; f < n; ++f) {
    const auto& t = m.triangles[f];
    normal[f] = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
  }
  std::vector<std::uint32_t> offsets(m.positions.size() + 1, 0), around(3 * n);
  for (const auto& t : m.triangles)
    for (const std::uint32_t v : t) ++offsets[v + 1];
  for (std::size_t v = 0; v < m.positions.size(); ++v) offsets[v + 1] += offsets[v];
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::size_t f = 0; f < n; ++f)
    for (const std::uint32_t v : m.triangles[f]) around[fill[v]++] = std::uint32_t(f);
  const double cos_crease = std::cos(crease_degrees * 3.14159265358979323846 / 180.0);
  m.corner_normals.assign(3 * n, glm::vec3(0.0f));
  for (std::size_t f = 0; f < n; ++f) {
    const double lf = glm::length(normal[f]);
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 sum = normal[f];
      const std::uint32_t v = m.triangles[f][k];
      for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) {
        const std::uint32_t g = around[j];
        if (g == f || (!groups.empty() && groups[g] != groups[f])) continue;
        const double d = glm::dot(normal[f], normal[g]), lg = glm::length(normal[g]);
        if (std::abs(d) >= cos_crease * lf * lg) sum += d < 0.0 ? -normal[g] : normal[g];
      }
      m.corner_normals[3 * f + k] = glm::vec3(sum);
    }
  }
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
