#pragma once
// The Vulkan compute backend (docs/DESIGN.md, "Backends"): the kernels of src/flow/backend.hpp on a
// Vulkan device, with the CPU backend's semantics (same formulas, same operation order:
// results bit for bit on any device that honours `precise`; see shaders/flow_common.h).
//
// Use (e.g. for the CLI's --backend vulkan):
//   std::unique_ptr<ComputeBackend> be = make_vulkan_backend();   // owns its VulkanContext
//   be->set_field(field);                                          // uploads the grid once
//   be->vertex_velocities(view, samples, velocity);                // K1 + K2: one submit
//   be->sample_tests(positions, samples, sample_view, out);        // K3: one submit
// or make_vulkan_backend(context) to share a VulkanContext (e.g. with a VulkanPyramid).
//
// Residency. Every array stays in a device buffer across calls and grows by 1.5x size classes.
// vertex_velocities uploads the positions on every call, and the faces, vf_offsets and vf_faces
// only when they changed: each is compared (size, then memcmp) with a host shadow copy of what
// was last uploaded, which costs one extra host copy of the topology and a memcmp per call,
// far less than uploading it again. sample_tests uploads all of its inputs (they
// change every call). Counts go to a uniform block and group counts to an indirect dispatch
// buffer, so the two command buffers (K1 + K2 with a barrier between them; K3) are recorded
// once and replayed until a buffer moves to a larger size class.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "flow/backend.hpp"
#include "vk_context.hpp"

namespace fracref {

/// Counters for tests and diagnostics.
struct VulkanBackendStats {
  std::size_t records = 0;           ///< command-buffer recordings (both command buffers)
  std::size_t topology_uploads = 0;  ///< vertex_velocities calls that uploaded faces or the CSR
  std::size_t submits = 0;           ///< submits (each followed by a wait)
};

/// Not thread-safe; the context (when not owned) must outlive the backend.
class VulkanBackend final : public ComputeBackend {
 public:
  /// Uses `context` (not owned).
  /// \throw RunError when the device cannot read the needed formats (RGBA32F, RGBA32UI, RG32UI,
  ///        R32UI) as uniform texel buffers, or when Vulkan fails.
  explicit VulkanBackend(VulkanContext& context);
  /// Creates and owns its context.
  /// \throw RunError("vulkan backend: <why>") when no usable device exists (the reason lists
  ///        every device and why it was rejected, or says that no driver is installed).
  explicit VulkanBackend(const VulkanContextOptions& options);
  ~VulkanBackend() override;
  VulkanBackend(const VulkanBackend&) = delete;
  VulkanBackend& operator=(const VulkanBackend&) = delete;

  /// "vulkan (<device name>)", e.g. "vulkan (llvmpipe (LLVM 15.0.6, 256 bits))".
  std::string name() const override;
  /// VulkanPyramid::build with `options` (threads ignored). \throw as VulkanPyramid.
  std::vector<Grid3> build_pyramid(const Grid3& base, const PyramidOptions& options) override;
  /// Uploads `field` (it need not outlive the backend).
  /// \throw RunError when a dim is < 2, values.size() does not match, or the grid exceeds the
  ///        device's texel-buffer limit.
  void set_field(const FieldGrid4& field) override;
  /// K1 + K2 in one submit. \pre as vertex_velocities_cpu; sizes, the CSR's shape and every
  /// index are checked (indices only when the topology was uploaded).
  /// \throw RunError when set_field was not called, a size or index is wrong, an array exceeds
  ///        the device's limits (use the CPU backend), or Vulkan fails (e.g. device lost).
  void vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                         std::span<glm::vec4> velocity) override;
  /// K3 in one submit. \pre as sample_velocities_cpu (checked like vertex_velocities).
  /// \throw RunError as vertex_velocities.
  void sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                    const SampleView& samples, std::span<glm::vec4> out) override;

  const VulkanBackendStats& stats() const;
  VulkanContext& context();

 private:
  struct Impl;
  std::unique_ptr<VulkanContext> owned_;  // declared first: destroyed after impl_
  std::unique_ptr<Impl> impl_;
};

/// A Vulkan backend on `context` (not owned). \throw RunError as VulkanBackend.
std::unique_ptr<ComputeBackend> make_vulkan_backend(VulkanContext& context);
/// A Vulkan backend owning a context created with `options` (validation off unless asked for or
/// FRACREF_VK_VALIDATION=1). \throw RunError with a clear message when no device is usable.
std::unique_ptr<ComputeBackend> make_vulkan_backend(const VulkanContextOptions& options = {});

}  // namespace fracref
