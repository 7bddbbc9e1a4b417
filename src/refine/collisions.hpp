#pragma once
// The boundary and collision constraints of one flow step (paper 4.4): boundary vertices are
// projected back onto the exterior B; interior vertices may not leave B; and vertices of a pair
// that continuous collision detection finds colliding over the step keep their old position.
#include <cstddef>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "refine/exterior.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// A rim face (a face with a corner on B) is tested against B as a copy whose B corners are
/// pulled this fraction of the way to its centroid (it touches B at those corners by
/// construction). The containment splits judge rim faces the same way.
inline constexpr double kRimShrink = 0.02;

/// Moves every boundary vertex of `s` to its closest point on B.
void project_boundary_vertices(FractureSurface& s, const ExteriorSurface& exterior);

/// In the candidate positions x1, moves every boundary vertex of `s` that moves (x1 != x0) to its
/// closest point on B; one that stays is taken to be on B already.
void apply_boundary_constraint(const FractureSurface& s, const ExteriorSurface& exterior,
                               const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1);

/// Resets to x0 every interior vertex whose x1 would leave B, then runs continuous collision
/// detection of S against itself over the linear motion x0 → x1 (vertex–triangle and edge–edge,
/// pairs sharing a vertex skipped) and resets the vertices of every colliding pair, repeating
/// until the motion is collision-free (a reset vertex cannot cause a new collision with a
/// collision-free neighbour, but it can expose one; after a few rounds every vertex of any pair
/// found is reset; a pair that was already in contact before the step, which holding vertices
/// back cannot change, ends the rounds). `clearance`, when given, holds per vertex a lower bound
/// of its distance to B at x0 (negative: unknown); it is resized to the vertex count (new entries
/// unknown) and updated to bound the distance at x1, so the costly inside test runs only for
/// vertices that may have reached B; without it, vertices that stay put (x1 == x0) are not tested.
/// \pre x0 collision-free, x0.size() == x1.size() == s.positions.size().
/// \return the number of vertices reset.
std::size_t apply_collision_constraints(const FractureSurface& s, const ExteriorSurface& exterior,
                                        const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                        std::vector<float>* clearance = nullptr);

/// apply_collision_constraints for one step x0 → x1 applied again and again as other checks hold
/// more vertices back: the first call searches S and B; a later call whose x1 differs from what
/// the call before left only where vertices are back at x0 tests only the pairs that search let
/// through with a vertex changed since (the same answer as a new search, at a fraction of its
/// cost); a later call with any other change searches again. `clearance` as above, at x0 on every
/// call.
class StepCollisions {
 public:
  /// \pre s, exterior and x0 outlive this object and do not change; x0 collision-free.
  StepCollisions(const FractureSurface& s, const ExteriorSurface& exterior, const std::vector<glm::vec4>& x0);
  ~StepCollisions();
  /// As apply_collision_constraints. \pre x1.size() == x0.size().
  std::size_t apply(std::vector<glm::vec4>& x1, std::vector<float>* clearance = nullptr);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fracref
