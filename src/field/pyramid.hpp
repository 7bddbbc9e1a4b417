#pragma once
// The Gaussian pyramid of a scalar grid (paper section 4.2): the CPU twin of host/vk_pyramid.
//
// Arithmetic contract shared with shaders/pyramid_blur.comp, so both backends agree to the last
// few ulps (bit for bit when neither side fuses multiply-adds):
//  - weights: gaussian_weights(sigma), rounded to float once on the CPU and uploaded as they are;
//  - one 1D pass along an axis: acc = 0.0f; for k = -r..r in ascending order:
//    acc = acc + w[k+r] * src[clamp(c+k, 0, n-1)], each product and sum rounded to float;
//  - passes in the order x, then y, then z.
// Only the nodes kept by the 2x downsample are ever computed: the x pass at even x, the y pass at
// even (x, y), the z pass at even (x, y, z). Because each output depends only on the same inputs
// in the same order, this equals "blur the whole grid, then keep every second node" exactly.
#include <vector>

#include "field/grid.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct PyramidOptions {
  int levels = 5;      ///< number of levels, the base included; in [1, 8]
  float sigma = 1.0f;  ///< standard deviation of the blur, in cells of the finer level; > 0
  int threads = default_threads();     ///< CPU worker threads (>= 1); the result never depends on it
};

/// Normalised 1D Gaussian weights w[k+r] = exp(-k²/(2σ²)) / Σ, k in [-r, r], r = ceil(3σ)
/// (3σ evaluated in float). Evaluated and normalised in double, then rounded to float.
/// \pre sigma > 0 and finite, r <= kMaxBlurRadius. \throw InputError otherwise.
std::vector<float> gaussian_weights(float sigma);

/// The largest blur radius any backend supports (σ up to about 21 cells).
inline constexpr int kMaxBlurRadius = 64;

/// Throws InputError unless `base` and `options` satisfy build_pyramid_cpu's preconditions.
void check_pyramid_input(const Grid3& base, const PyramidOptions& options);

/// Dimensions of every level: level 0 is base_dims, level l+1 is (n+1)/2 per axis (at least 1).
std::vector<glm::uvec3> pyramid_level_dims(glm::uvec3 base_dims, int levels);

/// The Gaussian pyramid of `base`: level 0 is `base` unchanged; level l+1 keeps every second
/// node of level l blurred by a separable 3D Gaussian with clamp-to-edge borders:
/// dst(i,j,k) = blurred(2i,2j,2k). Every level has base's origin and twice the previous cell.
/// \pre options.levels in [1, 8], options.sigma > 0, options.threads >= 1, base dims all
///      >= 1 and base.values.size() == base.size(). \throw InputError otherwise.
std::vector<Grid3> build_pyramid_cpu(const Grid3& base, const PyramidOptions& options);

/// The full-resolution separable blur (x, then y, then z; same arithmetic as the pyramid) of
/// `grid`: same dims, origin and cell. Used by tests to check the pyramid against its definition.
/// \pre as build_pyramid_cpu for `grid` and `sigma`. \throw InputError otherwise.
Grid3 blur_cpu(const Grid3& grid, float sigma, int threads = default_threads());

}  // namespace fracref
