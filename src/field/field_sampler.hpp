#pragma once
// The sampled modified strength field ψ with its pyramid-averaged gradient, precomputed on the
// base grid so that evaluating (ψ, ∇ψ) at a point is one trilinear fetch (docs/DESIGN.md,
// "Pipeline", step 3).
#include <vector>

#include <glm/glm.hpp>

#include "field/grid.hpp"

namespace fracref {

/// (ψ, ∂ψ/∂x, ∂ψ/∂y, ∂ψ/∂z) at the nodes of the base grid, x fastest.
struct FieldGrid4 {
  glm::uvec3 dims{0, 0, 0};
  glm::dvec3 origin{0.0};
  double cell = 1.0;
  std::vector<glm::vec4> values;
};

/// Precomputes the paper's multi-resolution field (section 4.2) on the base grid: at every base
/// node, the value ψ̃ = (1/L) Σ_l ψ_l (each level's trilinear interpolation, taken in the level's
/// index space, where base node k sits at level coordinate k / 2^l exactly: the world positions'
/// rounding would give each level's interpolation a few ulps of noise), and its gradient, the
/// central difference of ψ̃ one base cell either side (one-sided at the grid's faces). So the
/// gradient averages the levels' (the coarse levels still reach far), and it is the slope of the
/// value the refiner samples: the energy it measures, Σ A ψ̃̄, is the one whose gradient the flow
/// follows. (Each level's own central difference, a level cell either side, is not: on a field
/// that changes within a coarse cell it differs from the interpolated slope, the step was then
/// no descent direction of the measured energy, and the flow stalled.)
/// \pre level 0 dims all >= 2.
/// \throw InputError when the pyramid is empty or a level is not laid out as build_pyramid_cpu
///        builds it (dims of pyramid_level_dims, the base's origin, 2^l times its cell).
FieldGrid4 precompute_field_gradient(const std::vector<Grid3>& pyramid);

/// Trilinear interpolation of a scalar grid at world point p, p clamped into the grid's box.
/// \pre dims all >= 1.
double sample_trilinear(const Grid3& grid, const glm::dvec3& p);

/// (ψ, ∇ψ) at world point p: trilinear interpolation of the four channels, p clamped into the
/// grid's box. Float arithmetic in the same order as shaders/flow_common.h so that both
/// backends agree: g = (p − origin) / cell; i = clamp(floor(g), 0, n − 2); t = g − i.
/// \pre dims all >= 2.
glm::vec4 sample_field(const FieldGrid4& field, const glm::vec3& p);

}  // namespace fracref
