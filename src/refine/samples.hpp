#pragma once
// Candidate refinement samples (paper 4.4): one random point per face (on its boundary edge for
// a face on the boundary of S) and one per non-manifold edge, from a counter-based hash of
// (seed, iteration, element) so that every backend tests the same points and runs repeat.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "refine/topology_edit.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// A counter-based hash: 32 well-mixed bits of (seed, iteration, element, stream).
std::uint32_t sample_hash(std::uint64_t seed, std::uint32_t iteration, std::uint32_t element, std::uint32_t stream);
/// A uniform float in [0, 1) from the hash's top 24 bits (exact in float).
float sample_uniform(std::uint64_t seed, std::uint32_t iteration, std::uint32_t element, std::uint32_t stream);

/// The candidates of one iteration, in a deterministic order (non-manifold edges by edge id,
/// then faces by face id), with the split each would make and its neighbourhood fan.
struct SampleSet {
  std::vector<glm::vec4> points;
  std::vector<SplitRequest> requests;
  std::vector<std::uint32_t> fan_offsets{0};
  std::vector<glm::uvec2> fan_pairs;   ///< neighbourhood triangle (s, a, b) per pair
  std::vector<float> psi_linear;       ///< ψ interpolated from the element's vertices (filled by the refiner)
};

/// Draws the candidates. A face sample is uniform over the face shrunk toward its centroid so
/// that each barycentric weight is at least 0.15; an edge sample is uniform on the edge's middle 70%. Element ids: face f is element f, non-manifold edge e is element
/// face_count + e. A face with a boundary edge samples on it (the first boundary edge in the
/// face's order, or one of two chosen by the hash); a face touching a non-manifold edge still
/// draws its interior sample; the refiner resolves conflicts. Samples closer than `min_distance`
/// to a vertex of their element are discarded, and samples on boundary edges closer than
/// max(min_distance, rim_min_distance).
/// \pre adjacency current.
SampleSet draw_samples(const FractureSurface& s, std::uint64_t seed, std::uint32_t iteration, float min_distance,
                       float rim_min_distance = 0.0f);

}  // namespace fracref
