#pragma once
// Building blocks of the Vulkan flow backend (host/vk_backend.cpp): resident arrays that grow
// by size classes, and a kernel whose descriptor set follows its arrays when they move.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vk_buffer.hpp"
#include "vk_pipeline.hpp"

namespace fracref {

/// A resident buffer read by kernels as a uniform texel buffer of `format` (a view over its whole
/// capacity) and/or bound as a storage or uniform buffer (`format` VK_FORMAT_UNDEFINED: no view).
/// It grows geometrically (VulkanBuffer::grow) and counts its moves in generation(), so that
/// descriptor sets and recorded command buffers that use it know when to be rebuilt.
class DeviceArray {
 public:
  /// \param name what the array holds, for error messages ("positions").
  /// \param texel_bytes the size of one element (of one texel when `format` is set).
  /// \throw RunError when Vulkan fails.
  DeviceArray(VulkanContext& context, std::string name, VkFormat format, std::uint32_t texel_bytes,
              VkBufferUsageFlags usage);
  ~DeviceArray();
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;

  /// Ensures room for `elements` elements; the contents are kept.
  /// \throw RunError when the count exceeds the device's texel-buffer or storage-buffer limit
  ///        (the message names the array, the count and the limit) or Vulkan fails.
  void reserve(std::size_t elements);

  /// Copies `bytes` to the start of the array, growing it first.
  void upload(const void* data, std::size_t bytes);

  /// Like upload, unless the bytes equal those of the last upload_if_changed (kept in a host
  /// shadow copy and compared with memcmp). \return true when it uploaded.
  bool upload_if_changed(const void* data, std::size_t bytes);

  /// Makes the next upload_if_changed upload whatever it is given.
  void forget_shadow() { shadow_valid_ = false; }

  VkBuffer handle() const { return buffer_.handle(); }
  VkBufferView view() const { return view_; }
  void* data() const { return buffer_.data(); }
  VkDeviceSize capacity() const { return buffer_.capacity(); }
  /// Incremented every time the buffer (and its view) is replaced.
  std::uint64_t generation() const { return generation_; }
  const std::string& name() const { return name_; }

 private:
  void make_view();

  VulkanContext& context_;
  std::string name_;
  VkFormat format_;
  std::uint32_t texel_bytes_;
  VkBufferUsageFlags usage_;
  VulkanBuffer buffer_;
  VkBufferView view_ = VK_NULL_HANDLE;
  std::uint64_t generation_ = 0;
  std::vector<std::byte> shadow_;
  bool shadow_valid_ = false;
};

/// A compute pipeline with its one descriptor set, whose binding i holds arrays[i] with the
/// pipeline's i-th binding type.
class FlowKernel {
 public:
  /// \throw RunError when Vulkan rejects the shader or the set cannot be allocated.
  FlowKernel(VulkanContext& context, std::span<const std::uint32_t> spirv, std::vector<BindingType> types,
             std::vector<const DeviceArray*> arrays, VkDescriptorPool pool);
  FlowKernel(const FlowKernel&) = delete;
  FlowKernel& operator=(const FlowKernel&) = delete;

  /// Rewrites the descriptor set when an array moved since the last refresh (or never was).
  /// \return true when it did: command buffers binding the set must then be recorded again.
  bool refresh();

  /// Binds the pipeline and the set, dispatches with the group count at `indirect_offset` of
  /// `indirect`.
  void record_dispatch(VkCommandBuffer commands, VkBuffer indirect, VkDeviceSize indirect_offset) const;

 private:
  VulkanContext& context_;
  ComputePipeline pipeline_;
  std::vector<const DeviceArray*> arrays_;
  std::vector<std::uint64_t> bound_;  // generation of each array when the set was written
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

/// A memory barrier from compute-shader writes to `dst_access` at `dst_stage`.
void flow_barrier(VkCommandBuffer commands, VkAccessFlags dst_access, VkPipelineStageFlags dst_stage);

}  // namespace fracref
