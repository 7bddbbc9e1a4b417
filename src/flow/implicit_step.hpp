#pragma once
// The semi-implicit flow step (the implicit fairing of Desbrun, Meyer, Schröder and Barr 1999):
// the area term of E, which is stiff, taken at the end of the step; the material term ∇ψ explicit.
//
// Derivation. E(S) = Σ_j A_j ψ̄_j. With the cotangents and ψ̄_j frozen at the current positions,
// the area part of ∂E/∂x_i is linear in the positions (Pinkall and Polthier 1993):
//     Σ_j ψ̄_j ∂A_j/∂x_i = Σ_k w_ik (x_i − x_k) = (L_ψ x)_i,
//     w_ik = ½ Σ_{faces j ∋ edge ik} ψ̄_j cot θ_j,   θ_j the angle of face j opposite edge ik,
// and the material part is M_i ∇ψ(x_i), M_i = Σ_{j∋i} A_j / 3 (the mass of velocity.hpp). The
// explicit flow is M dx/dt = −(L_ψ x + M ∇ψ) = M v, v the velocity of velocity.hpp. Taking L_ψ x
// at the end of the step (backward Euler in the stiff term, Desbrun et al. 1999) and writing the
// step as a displacement d = x_{n+1} − x_n:
//     (M + dt L_ψ) d = dt M v.
// L_ψ is positive semi-definite even where obtuse angles make weights negative: it is the sum
// over faces of ψ̄_j times the face's cotangent matrix, the Dirichlet energy of the linear
// functions on one triangle, which is never negative. (Clamping the negative weights instead
// would take the stiffness from exactly the slivers that need it: a rim vertex between obtuse
// slivers then got the full explicit step and folded its faces.) Its diagonal is positive:
// face j adds ψ̄_j (cot β + cot γ)/2 = ψ̄_j |e_i|²/(4 A_j) > 0 at corner i. So M + dt L_ψ is
// symmetric positive definite, and d = 0 ⇔ v = 0: the fixed points are E's stationary points.
// For small dt the step is dt·v, the explicit step; for large dt it is a proximal step in which a
// vertex's reach is limited by its neighbours, not by its shortest edge, so dt is set by the
// scene. The three coordinates share the matrix: conjugate gradients run on the stacked 3n
// system, Jacobi-preconditioned.
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "flow/velocity.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct ImplicitStepOptions {
  int max_iterations = 50;   ///< conjugate-gradient iterations at most
  double tolerance = 1e-3;   ///< stop when the preconditioned residual falls below this fraction of the first
  int threads = default_threads();
};

struct ImplicitStepStats {
  int iterations = 0;
  double relative_residual = 0.0;
};

/// Solves (M + dt L_ψ) d = dt M v for the displacement d of every vertex (formula above), with M
/// and v the mass and velocity of vertex_velocities_cpu (velocity[i] = (v_i, M_i)) and ψ the
/// samples' x channel. `filter`, when not empty, holds per vertex an orthogonal projector P_i
/// (identity, onto a plane, onto a line, or zero) that d_i must lie in: the solve is then the
/// filtered conjugate gradients of Baraff and Witkin 1998, the minimiser of the step's quadratic
/// over the allowed motions, still a descent direction of E (d·∇E = −dᵀ(M + dt L_ψ)d / dt < 0).
/// A vertex with zero mass (all its faces degenerate) does not move.
/// The solve starts from the guess in `displacement` (zeros, or the last step's motion: conjugate
/// gradients are slow on the large-scale motion, which changes little from step to step).
/// Deterministic: the same bytes for any thread count.
/// \pre samples and velocity of `surface`'s positions; displacement.size() == positions.size();
///      filter empty or of that size, each a symmetric idempotent matrix; dt >= 0.
ImplicitStepStats implicit_step(const SurfaceView& surface, std::span<const glm::vec4> samples,
                                std::span<const glm::vec4> velocity, double dt, std::span<const glm::dmat3> filter,
                                std::span<glm::dvec3> displacement, const ImplicitStepOptions& options = {});

/// The cotangents of triangle (p, a, b) at a and at b (the angles opposite edges pb and pa), the
/// same arithmetic as implicit_step's weights; (0, 0) for a degenerate triangle. The sample tests
/// use them to give a sample the same implicit step as a vertex.
glm::dvec2 corner_cotangents(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b);

}  // namespace fracref
