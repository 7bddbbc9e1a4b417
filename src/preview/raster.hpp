#pragma once
// A small deterministic CPU rasterizer for preview pictures: z-buffered, flat-lit triangles.
#include <array>
#include <cstdint>
#include <filesystem>
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
};

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

/// Lays images out left to right, top to bottom, `columns` per row (a contact sheet).
/// \pre all images have the same size.
Image contact_sheet(const std::vector<Image>& images, int columns);

/// Writes the image as PNG through a temporary file and a rename. \throw RunError on failure.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace fracref
