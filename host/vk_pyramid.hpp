#pragma once
// The Gaussian pyramid on Vulkan: the same levels as build_pyramid_cpu (src/field/pyramid.hpp),
// from resident buffers and a command buffer recorded once and replayed on every build.
#include <cstddef>
#include <memory>
#include <vector>

#include "field/pyramid.hpp"
#include "vk_buffer.hpp"
#include "vk_pipeline.hpp"

namespace fracref {

/// Builds Gaussian pyramids with shaders/pyramid_blur.comp: per level three decimating 1D
/// passes (x, y, z) separated by barriers, reading through uniform texel buffers and writing
/// to storage buffers. Buffers and the command buffer are kept and reused while the base dims
/// and the options (levels, sigma) stay the same. Not thread-safe; `context` must outlive it.
class VulkanPyramid {
 public:
  /// \throw InputError for options outside build_pyramid_cpu's preconditions; RunError when
  ///        Vulkan fails.
  explicit VulkanPyramid(VulkanContext& context, const PyramidOptions& options = {});
  ~VulkanPyramid();
  VulkanPyramid(const VulkanPyramid&) = delete;
  VulkanPyramid& operator=(const VulkanPyramid&) = delete;

  /// New options; the next build re-records if levels or sigma changed (threads is ignored).
  /// \throw InputError for options outside build_pyramid_cpu's preconditions.
  void set_options(const PyramidOptions& options);
  const PyramidOptions& options() const { return options_; }

  /// Allocates the buffers and records the commands for bases of `dims` now (build does it on
  /// demand), e.g. to keep that cost out of a timing. \throw InputError when a dim is 0;
  /// RunError when Vulkan fails or the grid exceeds the device's buffer or dispatch limits.
  void prepare(glm::uvec3 dims);

  /// The pyramid of `base`: the same levels as build_pyramid_cpu(base, options()), to float
  /// rounding (bit for bit on a device that does not fuse multiply-adds). One submit, one wait.
  /// \throw InputError when `base` violates build_pyramid_cpu's preconditions; RunError when
  ///        Vulkan fails.
  std::vector<Grid3> build(const Grid3& base);

  /// The resident buffer holding level `level` of the last build (floats, x fastest, in the
  /// first 4 * nodes bytes of its capacity), for kernels that read the pyramid on the device:
  /// bind it as a uniform texel buffer or storage buffer. Valid until the next prepare or build
  /// with other dims or options. \throw RunError when the last build had no such level.
  const VulkanBuffer& level_buffer(int level) const;

  /// How many times the command buffer has been recorded (for tests and diagnostics).
  std::size_t record_count() const { return record_count_; }

 private:
  void allocate(const std::vector<glm::uvec3>& dims);
  void write_descriptors(const std::vector<glm::uvec3>& dims);
  void record(const std::vector<glm::uvec3>& dims);
  void destroy_views() noexcept;

  VulkanContext& context_;
  PyramidOptions options_;
  std::unique_ptr<ComputePipeline> blur_;
  VulkanBuffer weights_;
  std::vector<VulkanBuffer> levels_;  // level l of the pyramid
  VulkanBuffer after_x_, after_y_;    // the pass outputs inside a level, reused by every level
  std::vector<VkBufferView> views_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> sets_;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  glm::uvec3 recorded_dims_{0, 0, 0};
  PyramidOptions recorded_options_{.levels = 0};
  std::size_t record_count_ = 0;
  bool built_ = false;  // the level buffers hold the pyramid of the recorded shape
};

}  // namespace fracref
