#pragma once
// The modified strength field of paper 4.2 on its grid: ψ = w_ζ·ζ + w_d·d/diag + ψ0, where ζ is
// the material strength and d the distance to the coarse fracture surface (the paper's ξ = −d),
// measured in units of the exterior's bounding-box diagonal so the weights mean the same on any
// object size.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "field/grid.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// The weights of ψ: the scene file's `weights` section (defaults and checks there; offset > 0).
struct FieldWeights {
  double strength = 1.0;  ///< w_ζ
  double distance = 4.0;  ///< w_d, per diagonal of distance
  double offset = 0.05;   ///< ψ0
};

/// Distance from every node of `grid` (values ignored) to the triangle mesh, in scene units.
/// Uses a BVH and `threads` threads; deterministic, each value exactly the least distance to a
/// triangle as closest_point_on_triangle measures it.
/// \pre the mesh has at least one triangle.
Grid3 distance_grid(const Grid3& grid, const std::vector<glm::dvec3>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles, int threads = default_threads());

/// ψ at every node: w.strength·ζ + w.distance·d/diagonal + w.offset (> 0 by the scene's checks).
/// \pre zeta and distance have the same dims; diagonal > 0.
Grid3 modified_field(const Grid3& zeta, const Grid3& distance, const FieldWeights& w, double diagonal);

}  // namespace fracref
