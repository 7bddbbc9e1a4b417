#include "vk_buffer.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>


namespace fracref {

VulkanBuffer::VulkanBuffer(VulkanContext& context, VkDeviceSize bytes, VkBufferUsageFlags usage)
    : context_(&context), capacity_(std::max<VkDeviceSize>(bytes, 16)), usage_(usage) {
  const VkDevice device = context.device();
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = capacity_;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  try {
    vk_check(vkCreateBuffer(device, &info, nullptr, &buffer_), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer_, &req);
    auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    // Host-cached where there is such memory: the CPU reads the results (and grow() the old
    // contents) through the mapping, and on a discrete GPU reads of device-local memory through
    // the BAR are uncached, which would make every call slower than the CPU backend. On lavapipe
    // the one memory type is all of these at once.
    alloc.memoryTypeIndex =
        context.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                            VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    const std::string what = "vkAllocateMemory of " + std::to_string(req.size) + " bytes";
    vk_check(vkAllocateMemory(device, &alloc, nullptr, &memory_), what.c_str());
    vk_check(vkBindBufferMemory(device, buffer_, memory_, 0), "vkBindBufferMemory");
    vk_check(vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  } catch (...) {
    release();
    throw;
  }
}

VulkanBuffer::~VulkanBuffer() { release(); }

VulkanBuffer::VulkanBuffer(VulkanBuffer&& other) noexcept { *this = std::move(other); }

VulkanBuffer& VulkanBuffer::operator=(VulkanBuffer&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    mapped_ = std::exchange(other.mapped_, nullptr);
    capacity_ = std::exchange(other.capacity_, 0);
    usage_ = std::exchange(other.usage_, 0);
  }
  return *this;
}

bool VulkanBuffer::grow(VkDeviceSize bytes) {
  if (bytes <= capacity_) return false;
  const VkDeviceSize target = std::max(bytes, capacity_ + capacity_ / 2);
  VulkanBuffer bigger(*context_, target, usage_);
  if (mapped_) std::memcpy(bigger.mapped_, mapped_, capacity_);
  *this = std::move(bigger);
  return true;
}

void VulkanBuffer::release() noexcept {
  if (!context_) return;
  const VkDevice device = context_->device();
  if (mapped_) vkUnmapMemory(device, memory_);
  if (buffer_) vkDestroyBuffer(device, buffer_, nullptr);
  if (memory_) vkFreeMemory(device, memory_, nullptr);
  mapped_ = nullptr;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  capacity_ = 0;
}

}  // namespace fracref
