#pragma once
// Rigid motion of a piece: the best rotation and translation taking its rest vertices to a
// frame's (Horn 1987, "Closed-form solution of absolute orientation using unit quaternions"),
// used by animation.glb to move rigid pieces by node transforms instead of morph targets.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace fracref {

/// x = rotation * (X - pivot) + translation.
struct RigidPose {
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  ///< unit
  glm::dvec3 translation{0.0};
};

/// The pose minimising sum |R (rest[i] - pivot) + t - moved[i]|^2 over i in [0, count), in
/// double; the quaternion has w >= 0 unless that flips it away from `near` (then it is the one
/// of the pair closer to `near`, for interpolation without a turn the long way round).
/// \pre rest and moved hold `count` points, count >= 1. Degenerate point sets (fewer than three
///      independent points) give one of the fitting poses, which the caller verifies.
RigidPose fit_rigid(const glm::dvec3* rest, const glm::dvec3* moved, std::size_t count, const glm::dvec3& pivot,
                    const glm::dquat& near = glm::dquat(1.0, 0.0, 0.0, 0.0));

/// The eigenvector of the largest eigenvalue of a symmetric 4x4 matrix (cyclic Jacobi), unit.
glm::dvec4 largest_eigenvector(const glm::dmat4& symmetric);

}  // namespace fracref
