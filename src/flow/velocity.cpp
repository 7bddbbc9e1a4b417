#include "flow/velocity.hpp"

#include <vector>

#include "util/parallel.hpp"

namespace fracref {
namespace {

// Small ranges on the caller; larger ones in dynamic chunks (util/parallel.hpp), which keep both
// cores busy where two fixed halves waited on the slower one.
template <class Fn>
void parallel_for(std::size_t n, int threads, Fn fn) {
  if (threads <= 1 || n < 4096) {
    fn(std::size_t(0), n);
    return;
  }
  parallel_chunks(n, chunk_count(n, 2048), threads, [&](std::size_t, std::size_t b, std::size_t e) { fn(b, e); });
}

}  // namespace

void sample_vertices_cpu(const FieldGrid4& field, std::span<const glm::vec4> positions,
                         std::span<glm::vec4> samples, int threads) {
  parallel_for(positions.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) samples[i] = sample_field(field, glm::vec3(positions[i]));
  });
}

void accumulate_face_gradient(const glm::vec3& xi, const glm::vec3& xa, const glm::vec3& xb,
                              const glm::vec4& si, float psi_a, float psi_b, glm::vec3& grad,
                              float& mass) {
  glm::vec3 c = glm::cross(xa - xi, xb - xi);
  float twice_area = glm::length(c);
  if (!(twice_area > 0.0f)) return;
  glm::vec3 n = c / twice_area;
  float third_area = twice_area * (1.0f / 6.0f);
  float psi_mean = (si.x + psi_a + psi_b) * (1.0f / 3.0f);
  grad += third_area * glm::vec3(si.y, si.z, si.w) + 0.5f * psi_mean * glm::cross(n, xb - xa);
  mass += third_area;
}

void vertex_velocities_cpu(const SurfaceView& s, std::span<const glm::vec4> samples,
                           std::span<glm::vec4> velocity, int threads) {
  parallel_for(s.positions.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      glm::vec3 xi(s.positions[i]), grad(0.0f);
      float mass = 0.0f;
      for (std::uint32_t k = s.vf_offsets[i]; k < s.vf_offsets[i + 1]; ++k) {
        glm::uvec4 f = s.faces[s.vf_faces[k]];
        std::uint32_t a = f.y, bb = f.z;
        if (f.y == i) a = f.z, bb = f.x;
        else if (f.z == i) a = f.x, bb = f.y;
        accumulate_face_gradient(xi, glm::vec3(s.positions[a]), glm::vec3(s.positions[bb]), samples[i],
                                 samples[a].x, samples[bb].x, grad, mass);
      }
      velocity[i] = mass > 0.0f ? glm::vec4(-grad / mass, mass) : glm::vec4(0.0f);
    }
  });
}

double surface_energy(const SurfaceView& s, std::span<const glm::vec4> samples) {
  // The faces' terms side by side, their sum in face order: the same double as a serial loop.
  std::vector<double> term(s.faces.size());
  parallel_for(s.faces.size(), 2, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const glm::uvec4 f = s.faces[j];
      glm::dvec3 a(s.positions[f.x]), bb(s.positions[f.y]), c(s.positions[f.z]);
      double area = 0.5 * glm::length(glm::cross(bb - a, c - a));
      term[j] = area * (double(samples[f.x].x) + samples[f.y].x + samples[f.z].x) / 3.0;
    }
  });
  double energy = 0.0;
  for (double t : term) energy += t;
  return energy;
}

}  // namespace fracref
