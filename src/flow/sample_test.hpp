#pragma once
// K3: the velocity of candidate refinement samples (paper 4.4). A sample sits on a face or an
// edge of S; its neighbourhood is the set of triangles that splitting there would create around
// it, given as (a, b) pairs: triangle (s, a, b) in that order. shaders/flow_samples.comp is the
// GLSL twin.
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "field/field_sampler.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// Candidate samples and their neighbourhoods, flat.
struct SampleView {
  std::span<const glm::vec4> points;          ///< xyz = sample position
  std::span<const std::uint32_t> fan_offsets; ///< size points.size() + 1
  std::span<const glm::uvec2> fan_pairs;      ///< (a, b): neighbourhood triangle (s, a, b)
};

/// out[k] = (v_s, ψ(s)): the velocity of sample k by equation 3 over its own neighbourhood
/// (same formula and arithmetic as vertex_velocities_cpu), and ψ at the sample.
/// \pre vertex_samples from sample_vertices_cpu on `positions`; out.size() == points.size().
void sample_velocities_cpu(const FieldGrid4& field, std::span<const glm::vec4> positions,
                           std::span<const glm::vec4> vertex_samples, const SampleView& samples,
                           std::span<glm::vec4> out, int threads = default_threads());

}  // namespace fracref
