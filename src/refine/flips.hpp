#pragma once
// Edge flips that remove slim triangles (paper 4.4) without changing the shape or raising the
// energy, never on special (boundary or non-manifold) edges.
#include <cstddef>
#include <functional>
#include <span>

#include <glm/glm.hpp>

#include "refine/exterior.hpp"
#include "surface/fracture_surface.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct FlipOptions {
  double min_angle = 20.0;     ///< degrees: only edges of a face with a smaller angle are candidates
  double max_dihedral = 25.0;  ///< degrees: the two faces must be this close to coplanar
  int threads = default_threads();             ///< for the exact guard's tests (the result does not depend on it)
  /// When set, a flip is not made when this holds for one of its two new faces (the refiner's
  /// contact rule with B: refine/exterior_contact.hpp).
  std::function<bool(const glm::uvec4& face)> reject_face;
  /// When set, a flip is not made when this holds for its new edge (the refiner: a chord, an
  /// interior edge between two vertices on B, which a flip on a flat part of B would lay on B).
  std::function<bool(std::uint32_t a, std::uint32_t b)> reject_diagonal;
};

/// One pass over the regular edges in id order: flips an edge when one of its faces has an angle
/// below min_angle, the flip raises the smaller of the two faces' minimum angles, the faces are
/// within max_dihedral of coplanar (so the shape barely changes), both new faces keep the old
/// orientation, the faces around each junction (non-manifold) edge among the quad's four outer
/// edges keep their cyclic order (flip_keeps_junction_order; at most one flip turns a face about
/// each junction edge per pass), and the energy Σ A ψ̄ (ψ per vertex from `samples`) does not rise, and neither new face meets another
/// face of S (exact test: S stays free of self-intersections). The flips are made first and
/// checked together afterwards: one whose faces meet a face of S, or the later of two whose faces
/// meet, is undone, and so on until the faces restored meet nothing. Faces touched by one flip
/// (made or undone) are not flipped again in the same pass. Rebuilds the adjacency when anything
/// flipped.
/// \return the number of flips.
std::size_t flip_slim_triangles(FractureSurface& s, std::span<const glm::vec4> samples, const ExteriorSurface& exterior,
                                const FlipOptions& options);

}  // namespace fracref
