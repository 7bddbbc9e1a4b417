#include "vk_flow_kernel.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "util/error.hpp"

namespace fracref {

DeviceArray::DeviceArray(VulkanContext& context, std::string name, VkFormat format, std::uint32_t texel_bytes,
                         VkBufferUsageFlags usage)
    : context_(context), name_(std::move(name)), format_(format), texel_bytes_(texel_bytes), usage_(usage),
      buffer_(context, texel_bytes, usage) {
  make_view();
}

DeviceArray::~DeviceArray() {
  if (view_) vkDestroyBufferView(context_.device(), view_, nullptr);
}

void DeviceArray::reserve(std::size_t elements) {
  const VkPhysicalDeviceLimits& lim = context_.limits();
  const VkDeviceSize bytes = VkDeviceSize(elements) * texel_bytes_;
  const bool texel = format_ != VK_FORMAT_UNDEFINED;
  const bool storage = usage_ & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  if ((texel && elements > lim.maxTexelBufferElements) || (storage && bytes > lim.maxStorageBufferRange)) {
    throw RunError("vulkan backend: " + std::to_string(elements) + " " + name_ + " exceed the limits of " +
                   context_.describe() + " (maxTexelBufferElements " + std::to_string(lim.maxTexelBufferElements) +
                   ", maxStorageBufferRange " + std::to_string(lim.maxStorageBufferRange) +
                   " bytes): use the CPU backend");
  }
  if (!buffer_.grow(bytes)) return;
  // The old view went with the old buffer's handle; it may still be named by descriptor sets,
  // which FlowKernel::refresh rewrites because the generation changed.
  if (view_) vkDestroyBufferView(context_.device(), view_, nullptr);
  view_ = VK_NULL_HANDLE;
  ++generation_;
  make_view();
}

void DeviceArray::upload(const void* data, std::size_t bytes) {
  reserve((bytes + texel_bytes_ - 1) / texel_bytes_);
  if (bytes) std::memcpy(buffer_.data(), data, bytes);
  shadow_valid_ = false;
}

bool DeviceArray::upload_if_changed(const void* data, std::size_t bytes) {
  if (shadow_valid_ && shadow_.size() == bytes && (bytes == 0 || std::memcmp(shadow_.data(), data, bytes) == 0)) {
    return false;
  }
  upload(data, bytes);
  const auto* p = static_cast<const std::byte*>(data);
  shadow_.assign(p, p + bytes);
  shadow_valid_ = true;
  return true;
}

void DeviceArray::make_view() {
  if (format_ == VK_FORMAT_UNDEFINED) return;
  const VkDeviceSize texels =
      std::min<VkDeviceSize>(buffer_.capacity() / texel_bytes_, context_.limits().maxTexelBufferElements);
  auto info = vk_struct<VkBufferViewCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO);
  info.buffer = buffer_.handle();
  info.format = format_;
  info.range = texels * texel_bytes_;
  vk_check(vkCreateBufferView(context_.device(), &info, nullptr, &view_), "vkCreateBufferView");
}

FlowKernel::FlowKernel(VulkanContext& context, std::span<const std::uint32_t> spirv, std::vector<BindingType> types,
                       std::vector<const DeviceArray*> arrays, VkDescriptorPool pool)
    : context_(context), pipeline_(context, spirv, std::move(types), 0), arrays_(std::move(arrays)) {
  const VkDescriptorSetLayout layout = pipeline_.set_layout();
  auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  vk_check(vkAllocateDescriptorSets(context.device(), &alloc, &set_), "vkAllocateDescriptorSets");
}

bool FlowKernel::refresh() {
  std::vector<std::uint64_t> now;
  for (const DeviceArray* a : arrays_) now.push_back(a->generation());
  if (now == bound_) return false;
  const VkPhysicalDeviceLimits& lim = context_.limits();
  const std::size_t n = arrays_.size();
  std::vector<VkDescriptorBufferInfo> infos(n);
  std::vector<VkBufferView> views(n);
  std::vector<VkWriteDescriptorSet> writes(n);
  for (std::size_t b = 0; b < n; ++b) {
    const BindingType type = pipeline_.bindings()[b];
    writes[b] = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[b].dstSet = set_;
    writes[b].dstBinding = std::uint32_t(b);
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = descriptor_type(type);
    if (type == BindingType::UniformTexelBuffer || type == BindingType::StorageTexelBuffer) {
      views[b] = arrays_[b]->view();
      writes[b].pTexelBufferView = &views[b];
    } else {
      const VkDeviceSize limit =
          type == BindingType::UniformBuffer ? lim.maxUniformBufferRange : lim.maxStorageBufferRange;
      infos[b] = {arrays_[b]->handle(), 0, std::min(arrays_[b]->capacity(), limit)};
      writes[b].pBufferInfo = &infos[b];
    }
  }
  vkUpdateDescriptorSets(context_.device(), std::uint32_t(n), writes.data(), 0, nullptr);
  bound_ = std::move(now);
  return true;
}

void FlowKernel::record_dispatch(VkCommandBuffer commands, VkBuffer indirect, VkDeviceSize indirect_offset) const {
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.handle());
  vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.layout(), 0, 1, &set_, 0, nullptr);
  vkCmdDispatchIndirect(commands, indirect, indirect_offset);
}

void flow_barrier(VkCommandBuffer commands, VkAccessFlags dst_access, VkPipelineStageFlags dst_stage) {
  auto barrier = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, dst_stage, 0, 1, &barrier, 0, nullptr, 0,
                       nullptr);
}

}  // namespace fracref
