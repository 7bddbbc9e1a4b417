#include "flow/sample_test.hpp"

#include <vector>

#include "flow/velocity.hpp"
#include "util/parallel.hpp"

namespace fracref {

void sample_velocities_cpu(const FieldGrid4& field, std::span<const glm::vec4> positions,
                           std::span<const glm::vec4> vertex_samples, const SampleView& samples,
                           std::span<glm::vec4> out, int threads) {
  auto work = [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      glm::vec3 xs(samples.points[k]);
      glm::vec4 ss = sample_field(field, xs);
      glm::vec3 grad(0.0f);
      float mass = 0.0f;
      for (std::uint32_t q = samples.fan_offsets[k]; q < samples.fan_offsets[k + 1]; ++q) {
        glm::uvec2 ab = samples.fan_pairs[q];
        accumulate_face_gradient(xs, glm::vec3(positions[ab.x]), glm::vec3(positions[ab.y]), ss,
                                 vertex_samples[ab.x].x, vertex_samples[ab.y].x, grad, mass);
      }
      out[k] = glm::vec4(mass > 0.0f ? -grad / mass : glm::vec3(0.0f), ss.x);
    }
  };
  std::size_t n = samples.points.size();
  if (threads <= 1 || n < 4096) return work(0, n);
  parallel_chunks(n, chunk_count(n, 2048), threads, [&](std::size_t, std::size_t b, std::size_t e) { work(b, e); });
}

}  // namespace fracref
