#include "refine/relaxation.hpp"

namespace fracref {
namespace {

// The relaxation of vertex i at the moved positions y: zero for a rim or junction vertex.
glm::dvec3 relaxation_of(const FractureSurface& s, const std::vector<glm::dvec3>& y, std::uint32_t i, double fraction) {
  if (s.vertex_flags[i] & (kVertexBoundary | kVertexNonManifold)) return glm::dvec3(0.0);
  glm::dvec3 centroid(0.0), normal(0.0);
  int corners = 0;
  for (std::uint32_t k = s.vf_offsets[i]; k < s.vf_offsets[i + 1]; ++k) {
    const glm::uvec4 f = s.faces[s.vf_faces[k]];
    normal += glm::cross(y[f.y] - y[f.x], y[f.z] - y[f.x]);
    for (int c = 0; c < 3; ++c)
      if (f[c] != i) centroid += y[f[c]], ++corners;
  }
  if (corners == 0) return glm::dvec3(0.0);
  glm::dvec3 t = centroid / double(corners) - y[i];
  // The faces' winding may differ between sheets, but a vertex inside one sheet has one winding.
  const double len = glm::length(normal);
  if (len > 0.0) normal /= len, t -= glm::dot(t, normal) * normal;
  return fraction * t;
}

}  // namespace

void add_tangential_relaxation(const FractureSurface& s, std::span<const glm::vec4> x, std::vector<glm::dvec3>& d,
                               const RelaxationOptions& o) {
  if (o.fraction <= 0.0) return;
  std::vector<glm::dvec3> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = glm::dvec3(glm::vec3(x[i])) + d[i];
  std::vector<glm::dvec3> add(x.size());
  parallel_chunks(x.size(), chunk_count(x.size(), 4096), o.threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) add[i] = relaxation_of(s, y, std::uint32_t(i), o.fraction);
  });
  for (std::size_t i = 0; i < x.size(); ++i) d[i] += add[i];
}

}  // namespace fracref
