#pragma once
// A small deterministic CPU rasterizer for preview pictures: z-buffered triangles, flat-lit or
// lit per pixel from corner normals and colours.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// An RGB8 image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 bytes per pixel
};

/// Triangles to draw, each with its own colour (linear RGB in [0,1]).
struct PreviewMesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<glm::vec3> triangle_colors;  ///< one per triangle
  /// Optional, 3 per triangle (corner k of triangle f at 3f + k): normals blended across the
  /// triangle, so that a curved surface made of flat triangles reads as curved. Empty: the
  /// triangle's own normal.
  std::vector<glm::vec3> corner_normals;
  /// Optional: the colour at each pixel, from the triangle and the pixel's barycentric
  /// coordinates in it (a texture), in place of triangle_colors. What it refers to must outlive
  /// render_preview.
  std::function<glm::vec3(std::size_t triangle, const glm::dvec3& barycentric)> paint;
};

/// Fills m.corner_normals: at each corner, the area-weighted mean of the normals of the triangles
/// around that vertex in the same group (`groups`, one per triangle; empty = one group) whose
/// normal is within `crease_degrees` of the corner's triangle's, either way round (fracture
/// sheets are drawn two-sided and their faces need not agree on a side). So a crease sharper
/// than the limit, and the line between two groups, stay sharp.
/// \pre groups is empty or has one entry per triangle.
void smooth_corner_normals(PreviewMesh& m, double crease_degrees, const std::vector<int>& groups = {});

struct RenderOptions {
  int width = 960;
  int height = 720;
  int supersample = 2;                            ///< samples per pixel axis (anti-aliasing)
  glm::dvec3 view_direction{-0.55, -0.45, -0.70}; ///< camera looks along this direction
  glm::dvec3 up{0.0, 1.0, 0.0};
  glm::dvec3 light_direction{-0.3, -0.8, -0.5};   ///< light travels along this direction
  glm::vec3 background{0.93f, 0.94f, 0.96f};
};

/// Renders the meshes with an orthographic camera fitted to their bounding box; both faces of a
/// triangle are lit (fracture surfaces are seen from both sides). Deterministic.
/// \pre every triangle index is in range, triangle_colors.size() == triangles.size().
Image render_preview(const std::vector<PreviewMesh>& meshes, const RenderOptions& options = {});

/// Writes the linear colour `c` (components clamped to [0, 1]) at pixel (x, y), sRGB-encoded as
/// render_preview writes every pixel; nothing outside the image.
void set_pixel(Image& image, int x, int y, const glm::vec3& c);

/// Lays images out left to right, top to bottom, `columns` per row (a contact sheet).
/// \pre all images have the same size.
Image contact_sheet(const std::vector<Image>& images, int columns);

/// Writes the image as PNG through a temporary file and a rename. \throw RunError on failure.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace fracref
