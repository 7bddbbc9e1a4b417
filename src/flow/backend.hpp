#pragma once
// The compute backend interface (docs/DESIGN.md, Backends): the three kernels the design card puts
// on the GPU, with one CPU implementation here and a Vulkan one in host/. Both have the same
// semantics; the refiner only talks to this interface.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "field/field_sampler.hpp"
#include "field/grid.hpp"
#include "field/pyramid.hpp"
#include "flow/sample_test.hpp"
#include "flow/velocity.hpp"
#include "util/parallel.hpp"

namespace fracref {

class ComputeBackend {
 public:
  virtual ~ComputeBackend() = default;
  /// "cpu" or "vulkan (<device>)".
  virtual std::string name() const = 0;
  /// The Gaussian pyramid of `base` (build_pyramid_cpu's semantics).
  virtual std::vector<Grid3> build_pyramid(const Grid3& base, const PyramidOptions& options) = 0;
  /// Makes `field` the field sampled by the two kernels below (uploaded once).
  /// \pre `field` outlives every later call (the CPU backend keeps a reference).
  virtual void set_field(const FieldGrid4& field) = 0;
  /// K1 + K2: samples[i] = (ψ, ∇ψ)(x_i), velocity[i] = (v_i, M_i).
  virtual void vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                                 std::span<glm::vec4> velocity) = 0;
  /// K3: out[k] = (v_s, ψ(s)) for every candidate sample.
  virtual void sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                            const SampleView& samples, std::span<glm::vec4> out) = 0;
};

/// The CPU backend: plain C++ on `threads` threads.
std::unique_ptr<ComputeBackend> make_cpu_backend(int threads = default_threads());

}  // namespace fracref
