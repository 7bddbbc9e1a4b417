#pragma once
// Which motions the flow allows each vertex of S: the filter of the implicit step
// (flow/implicit_step.hpp), a projector per vertex.
#include <vector>

#include <glm/glm.hpp>

#include "refine/exterior.hpp"
#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct MotionFilterOptions {
  bool rim_motion = false;  ///< let vertices on B slide on B (else they stay)
  bool tangential = true;   ///< let a vertex inside a sheet move along S (else along its normal only)
  int threads = default_threads();
};

/// Per vertex of `s`: the identity inside a sheet, or with options.tangential off the line of its
/// normal (the area-weighted mean of its faces' normals; the identity where they cancel);
/// across the junction curve for a vertex on a non-manifold curve (the identity where the curve
/// turns back at it, its two edges less than 90 degrees apart); for a vertex on B, zero, or
/// with rim_motion along B across the rim curve (along B freely where the rim is not a simple
/// curve).
/// \pre adjacency of s current.
std::vector<glm::dmat3> motion_filters(const FractureSurface& s, const ExteriorSurface& b,
                                       const MotionFilterOptions& options = {});

}  // namespace fracref
