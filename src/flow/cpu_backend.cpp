#include "flow/backend.hpp"

namespace fracref {
namespace {

class CpuBackend final : public ComputeBackend {
 public:
  explicit CpuBackend(int threads) : threads_(threads) {}
  std::string name() const override { return "cpu"; }
  std::vector<Grid3> build_pyramid(const Grid3& base, const PyramidOptions& options) override {
    PyramidOptions o = options;
    o.threads = threads_;
    return build_pyramid_cpu(base, o);
  }
  void set_field(const FieldGrid4& field) override { field_ = &field; }
  void vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                         std::span<glm::vec4> velocity) override {
    sample_vertices_cpu(*field_, surface.positions, samples, threads_);
    vertex_velocities_cpu(surface, samples, velocity, threads_);
  }
  void sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                    const SampleView& samples, std::span<glm::vec4> out) override {
    sample_velocities_cpu(*field_, positions, vertex_samples, samples, out, threads_);
  }

 private:
  int threads_;
  const FieldGrid4* field_ = nullptr;
};

}  // namespace

std::unique_ptr<ComputeBackend> make_cpu_backend(int threads) { return std::make_unique<CpuBackend>(threads); }

}  // namespace fracref
