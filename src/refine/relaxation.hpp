#pragma once
// Tangential relaxation of the fracture surface's sheets (refine.relax): a regularising motion
// added to the flow step, which evens the triangles out without moving the surface to first order.
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct RelaxationOptions {
  double fraction = 0.0;  ///< of the way to the ring's centroid, in [0, 1]; 0 adds nothing
  int threads = default_threads();
};

/// Adds to each motion d[i] of a vertex inside a sheet (neither on B nor on a junction) the
/// fraction of the way from its moved position y = x[i] + d[i] to the mean of its faces' other
/// corners at their moved positions, projected onto the plane normal to the area-weighted mean of
/// its faces' normals there (left whole where they cancel). Rim and junction vertices keep their
/// motion. Each vertex reads only y, so the result does not depend on `threads`.
/// \pre adjacency of s current; x.size() == d.size() == s.positions.size().
void add_tangential_relaxation(const FractureSurface& s, std::span<const glm::vec4> x, std::vector<glm::dvec3>& d,
                               const RelaxationOptions& options);

}  // namespace fracref
