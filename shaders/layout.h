// Structs shared by the C++ host and the GLSL compute shaders: one definition, two languages.
// Only 4-byte scalars and 16-byte vectors, so std430/push-constant layout equals C++ layout.
#ifndef FRACREF_LAYOUT_H
#define FRACREF_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace fracref::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using ivec4 = glm::ivec4;
#endif

/// Workgroup size of every 1D kernel (DESIGN.md: 32–256 perform alike on lavapipe).
#define FRACREF_WORKGROUP 64

// ---- Gaussian pyramid (blur along one axis, 2x downsample) ----
// Grids are x-fastest: index = x + nx*(y + ny*z).
struct BlurParams {
  uvec4 dims;      // nx, ny, nz, axis (0, 1, 2)
  uvec4 taps;      // radius, 0, 0, 0
};
struct DownsampleParams {
  uvec4 src_dims;  // nx, ny, nz, 0
  uvec4 dst_dims;  // (n+1)/2 per axis, 0
};

#ifdef __cplusplus
static_assert(sizeof(BlurParams) == 32);
static_assert(sizeof(DownsampleParams) == 32);
}  // namespace fracref::gpu
#endif

#endif
