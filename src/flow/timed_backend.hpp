#pragma once
// A ComputeBackend that forwards to another and adds up the wall time of each kernel: the
// per-kernel seconds of report.json and of the bench's scene table.
#include <chrono>

#include "flow/backend.hpp"

namespace fracref {

/// Seconds spent in each kernel (calls are synchronous: Vulkan transfers and waits included)
/// and how many calls each had.
struct KernelSeconds {
  double pyramid = 0.0, k1k2 = 0.0, k3 = 0.0;
  std::size_t pyramid_calls = 0, k1k2_calls = 0, k3_calls = 0;
};

/// Forwards every call to `inner` (which must outlive it) and times it.
class TimedBackend final : public ComputeBackend {
 public:
  explicit TimedBackend(ComputeBackend& inner) : inner_(inner) {}

  std::string name() const override { return inner_.name(); }
  std::vector<Grid3> build_pyramid(const Grid3& base, const PyramidOptions& options) override;
  void set_field(const FieldGrid4& field) override;
  void vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                         std::span<glm::vec4> velocity) override;
  void sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                    const SampleView& samples, std::span<glm::vec4> out) override;

  const KernelSeconds& seconds() const { return seconds_; }

 private:
  ComputeBackend& inner_;
  KernelSeconds seconds_;
};

}  // namespace fracref
