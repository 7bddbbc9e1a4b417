#pragma once
// The gradient flow of the paper's equation 3 on the non-manifold fracture surface: the CPU
// kernels K1 (sample ψ and ∇ψ at every vertex) and K2 (gather each vertex's velocity over the
// faces incident to it). shaders/flow_*.comp are their GLSL twins, with the same arithmetic.
//
// Derivation (docs/DESIGN.md, "The velocity"). The discrete energy is E(S) = Σ_j A_j ψ̄_j, with A_j
// the area of face j and ψ̄_j the mean of ψ at its three corners. For face j = (i, a, b) taken in
// its own orientation, with unit normal n̂_j:
//     ∂A_j/∂x_i = ½ n̂_j × (x_b − x_a),    ∂ψ̄_j/∂x_i = ⅓ ∇ψ(x_i),
// (the second with the paper's approximation that ∇ψ is constant over the 1-ring). The flow is
// the gradient descent of E with the lumped (barycentric) mass M_i = ⅓ Σ_{j∋i} A_j:
//     v_i = −(1/M_i) Σ_{j∋i} [ (A_j/3) ∇ψ(x_i) + ½ (n̂_j × (x_b − x_a)) ψ̄_j ].
// With ψ ≡ 1 this is −∇A/M_i, the cotangent mean-curvature normal of Meyer et al. 2002 with the
// barycentric vertex area. (The paper writes 1/A_i with A_i the 1-ring area; that only rescales
// time by 3, which the step-size rule absorbs.) Every face incident to i counts once, so
// non-manifold junction vertices are handled by the same sum.
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "field/field_sampler.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// Read-only flat arrays of a triangle surface and its vertex→faces CSR.
struct SurfaceView {
  std::span<const glm::vec4> positions;     ///< xyz used
  std::span<const glm::uvec4> faces;        ///< xyz = vertex ids in the face's orientation
  std::span<const std::uint32_t> vf_offsets;  ///< size positions.size() + 1
  std::span<const std::uint32_t> vf_faces;
};

/// K1: samples[i] = sample_field(field, x_i) = (ψ, ∇ψ) at every vertex.
/// \pre samples.size() == positions.size(); threads >= 1.
void sample_vertices_cpu(const FieldGrid4& field, std::span<const glm::vec4> positions,
                         std::span<glm::vec4> samples, int threads = default_threads());

/// K2: velocity[i] = (v_i, M_i) by the formula above; an isolated vertex or one whose faces are
/// all degenerate gets (0, 0, 0, 0).
/// \pre samples from sample_vertices_cpu; velocity.size() == positions.size().
void vertex_velocities_cpu(const SurfaceView& surface, std::span<const glm::vec4> samples,
                           std::span<glm::vec4> velocity, int threads = default_threads());

/// One face's contribution to vertex i = corner `k` (0, 1, 2) of `face`: accumulates
/// (A_j/3)∇ψ(x_i) + ½(n̂_j × (x_b − x_a))ψ̄_j into `grad` and A_j/3 into `mass`.
/// Shared by the vertex kernel and the sample tests so both use one formula.
void accumulate_face_gradient(const glm::vec3& xi, const glm::vec3& xa, const glm::vec3& xb,
                              const glm::vec4& si, float psi_a, float psi_b, glm::vec3& grad,
                              float& mass);

/// The discrete energy E(S) = Σ_j A_j ψ̄_j (double accumulation, deterministic order).
double surface_energy(const SurfaceView& surface, std::span<const glm::vec4> samples);

}  // namespace fracref
