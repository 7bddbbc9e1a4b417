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

/// Workgroup size of every 1D kernel: a multiple of every common subgroup width; the kernels are
/// bound by gathers, not by the workgroup's size.
#define FRACREF_WORKGROUP 64

// ---- Gaussian pyramid: one decimating 1D blur pass (shaders/pyramid_blur.comp) ----
// Grids are x-fastest: index = x + nx*(y + ny*z). A pass blurs along `axis` and keeps every
// second node along it: output coordinate c reads input coordinates clamp(2c + k, 0, n-1),
// k in [-r, r]; the other two coordinates are shared. Passes x, y, z make one pyramid level.
#define FRACREF_BLUR_MAX_RADIUS 64
#define FRACREF_BLUR_WEIGHT_VEC4S 33  // (2 * FRACREF_BLUR_MAX_RADIUS + 1 + 3) / 4
struct BlurParams {
  uvec4 src_dims;  // nx, ny, nz of the input, axis (0, 1, 2)
  uvec4 dst_dims;  // nx, ny, nz of the output ((n+1)/2 along axis), radius r
};
// The 2r+1 normalised weights w[k+r], four per vec4 (std140 uniform block: stride 16 both sides).
struct BlurWeights {
  vec4 w[FRACREF_BLUR_WEIGHT_VEC4S];
};

// ---- The flow kernels K1, K2, K3 (shaders/flow_sample.comp, flow_velocity.comp, flow_samples.comp) ----
// One uniform block shared by the three kernels, written by the host before every submit: the
// command buffers are recorded once per buffer size class and replayed, so the element counts
// (which change every call) cannot be push constants. Dispatch sizes come from an indirect
// buffer written at the same time.
struct FlowParams {
  uvec4 field_dims;    // nx, ny, nz of the FieldGrid4 (all >= 2), unused
  vec4 field_origin;   // x, y, z of node (0, 0, 0), cell size (floats, as sample_field uses them)
  uvec4 counts;        // vertices (K1, K2), samples (K3), unused, unused
};

#ifdef __cplusplus
static_assert(sizeof(BlurParams) == 32);
static_assert(sizeof(BlurWeights) == 16 * FRACREF_BLUR_WEIGHT_VEC4S);
static_assert(4 * FRACREF_BLUR_WEIGHT_VEC4S >= 2 * FRACREF_BLUR_MAX_RADIUS + 1);
static_assert(sizeof(FlowParams) == 48);
}  // namespace fracref::gpu
#endif

#endif
