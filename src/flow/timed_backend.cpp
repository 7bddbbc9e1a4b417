#include "flow/timed_backend.hpp"

namespace fracref {
namespace {

// Adds the time until destruction to `total` and counts the call.
class Stopwatch {
 public:
  Stopwatch(double& total, std::size_t& calls) : total_(total) { ++calls; }
  ~Stopwatch() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

std::vector<Grid3> TimedBackend::build_pyramid(const Grid3& base, const PyramidOptions& options) {
  Stopwatch w(seconds_.pyramid, seconds_.pyramid_calls);
  return inner_.build_pyramid(base, options);
}

// Uploading the field belongs to the pyramid's set-up cost (it is not counted as a call).
void TimedBackend::set_field(const FieldGrid4& field) {
  std::size_t uncounted = 0;
  Stopwatch w(seconds_.pyramid, uncounted);
  inner_.set_field(field);
}

void TimedBackend::vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                                     std::span<glm::vec4> velocity) {
  Stopwatch w(seconds_.k1k2, seconds_.k1k2_calls);
  inner_.vertex_velocities(surface, samples, velocity);
}

void TimedBackend::sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                                const SampleView& samples, std::span<glm::vec4> out) {
  Stopwatch w(seconds_.k3, seconds_.k3_calls);
  inner_.sample_tests(positions, vertex_samples, samples, out);
}

}  // namespace fracref
