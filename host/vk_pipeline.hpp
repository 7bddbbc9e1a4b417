#pragma once
// A compute pipeline built from SPIR-V embedded in the binary (`#include "spv/<stem>_spv.h"`),
// with one descriptor set whose bindings 0..n-1 have the given types, and push constants.
#include <cstdint>
#include <span>
#include <vector>

#include "vk_context.hpp"

namespace fracref {

/// What a shader binding holds; binding i of the set has the i-th type of the list.
enum class BindingType {
  StorageBuffer,       ///< `buffer { ... }` (SSBO): outputs, read-write arrays
  UniformBuffer,       ///< `uniform { ... }` (UBO): small constant tables
  UniformTexelBuffer,  ///< `samplerBuffer` + texelFetch: the fast read-only path on lavapipe
  StorageTexelBuffer,  ///< `imageBuffer` + imageLoad/imageStore
};

VkDescriptorType descriptor_type(BindingType type);

class ComputePipeline {
 public:
  /// \param spirv the words of a compute shader whose entry point is "main".
  /// \param bindings the type of binding 0, 1, ... of descriptor set 0.
  /// \param push_constant_bytes size of the push-constant block (0 for none; multiple of 4).
  /// \throw RunError when Vulkan rejects the shader or the layout.
  ComputePipeline(VulkanContext& context, std::span<const std::uint32_t> spirv, std::vector<BindingType> bindings,
                  std::uint32_t push_constant_bytes);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  const std::vector<BindingType>& bindings() const { return bindings_; }
  std::uint32_t push_constant_bytes() const { return push_bytes_; }

 private:
  void release() noexcept;

  VulkanContext& context_;
  std::vector<BindingType> bindings_;
  std::uint32_t push_bytes_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace fracref
