#pragma once
// Local checks of a flow step before it is taken: faces that the step would fold over, sheets
// that would pass through each other around a junction edge, and faces around a vertex that would
// cross (the collision search skips faces that share a vertex, so none would be seen there).
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct StepGuardOptions {
  /// A face whose normal, projected on its old normal, keeps less than this fraction of it (turned
  /// by more than 90 degrees, or collapsed) folds.
  double min_area_ratio = 0.05;
  /// Per face of S, B's outward unit normal where the face meets B along a boundary edge (zero for
  /// the others); may be empty. Such a rim face may not turn closer to B's tangent plane than
  /// min_rim_angle: the pieces stage re-triangulates a rim face from its inner corner toward its
  /// edge's path on B, which that corner must see past B's curvature.
  std::vector<glm::dvec3> rim_normals;
  double min_rim_angle = 20.0;  ///< degrees
};

/// Resets to x0 every corner of a face that the motion x0 → x1 folds or turns toward B (above),
/// and every vertex of the faces around a non-manifold edge whose cyclic order around the edge
/// the motion changes;
/// repeats until neither happens (holding vertices can fold a neighbour; every vertex held leaves
/// S as it was, so the loop ends). Returns the number of vertices reset.
/// \pre x0.size() == x1.size() == s.positions.size(); adjacency of s current.
std::size_t hold_folding_motion(const FractureSurface& s, const std::vector<glm::vec4>& x0,
                                std::vector<glm::vec4>& x1, const StepGuardOptions& options = {});

/// Whether hold_folding_motion would reset anything (x1 is not changed).
bool motion_folds(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                  const StepGuardOptions& options = {});

/// Resets to x0 the star (every face around it) of each vertex around which two faces that share
/// only that vertex intersect elsewhere at x1 but not at x0 (exact); repeats until none does.
/// Returns the number of vertices reset. The result does not depend on `threads`.
/// \pre as hold_folding_motion.
std::size_t hold_star_crossings(const FractureSurface& s, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                int threads = default_threads());

/// Whether hold_star_crossings would reset anything (x1 is not changed).
bool motion_crosses_stars(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                          int threads = default_threads());

/// The backtracking line search's stop (refine.cpp): whether E rises along a step at first order,
/// from the rises E − E(0) at twice a length (`rise_double`) and at the length (`rise`). The
/// parabola through (0, 0) and the two points has the slope (4·rise − rise_double) / (2·length)
/// at 0; when it is not negative and both rises are positive, the parabola is positive on the
/// whole of (0, length]: convex, it lies above its tangent at 0; concave, above its chord from
/// (0, 0) to (length, rise). So no shorter step lowers E, as far as a parabola describes it.
bool rises_at_first_order(double rise_double, double rise);

/// Resets to x0 each rim (boundary) vertex of `s` that moved (x1 != x0) and shares its position in
/// x1 with another rim vertex, until none does; returns the number of vertices reset. With the
/// rim sliding on B (refine.rim_motion), two rim vertices can land on one point of B (snapped
/// onto the same B edge), and the pieces stage would get two rim points at one place. When x0
/// has no such pair, x1 has none afterwards.
/// \pre x0.size() == x1.size() == s.positions.size().
std::size_t hold_coincident_rim(const FractureSurface& s, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1);

}  // namespace fracref
