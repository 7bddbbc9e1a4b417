#pragma once
// A Vulkan buffer in host-visible, host-coherent memory (host-cached where the device has it),
// mapped for its whole life: the CPU writes inputs and reads results straight through data().
// On lavapipe this is plain host memory; on a discrete GPU it is system memory the kernels reach
// over the bus. Not device-local memory mapped through the BAR: the CPU reads every result back,
// and reads through the BAR are uncached, which costs far more than the kernels' bus traffic.
#include <cstddef>
#include <cstdint>

#include "vk_context.hpp"

namespace fracref {

class VulkanBuffer {
 public:
  VulkanBuffer() = default;
  /// A buffer of at least `bytes` (at least 16) for `usage`.
  /// \throw RunError when the buffer or its memory cannot be created.
  VulkanBuffer(VulkanContext& context, VkDeviceSize bytes, VkBufferUsageFlags usage);
  ~VulkanBuffer();
  VulkanBuffer(VulkanBuffer&& other) noexcept;
  VulkanBuffer& operator=(VulkanBuffer&& other) noexcept;
  VulkanBuffer(const VulkanBuffer&) = delete;
  VulkanBuffer& operator=(const VulkanBuffer&) = delete;

  /// Ensures capacity() >= bytes. When it must grow, the new capacity is max(bytes, 1.5 x the
  /// old one), the old contents are copied over, and the handle changes (views and descriptor
  /// sets that refer to it must be rebuilt). \return true when the buffer was replaced.
  /// \pre the buffer was constructed with a context (it is not default-constructed).
  bool grow(VkDeviceSize bytes);

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize capacity() const { return capacity_; }
  void* data() const { return mapped_; }
  template <class T>
  T* as() const { return static_cast<T*>(mapped_); }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

 private:
  void release() noexcept;

  VulkanContext* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  VkDeviceSize capacity_ = 0;
  VkBufferUsageFlags usage_ = 0;
};

}  // namespace fracref
