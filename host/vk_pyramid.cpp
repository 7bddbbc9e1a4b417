#include "vk_pyramid.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "layout.h"
#include "spv/pyramid_blur_spv.h"
#include "util/error.hpp"

namespace fracref {
namespace {

static_assert(kMaxBlurRadius == FRACREF_BLUR_MAX_RADIUS, "CPU and shader radius limits differ");
constexpr int kMaxPasses = 3 * 7;  // three passes per level above the base, at most 8 levels
constexpr VkBufferUsageFlags kGridUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;

std::size_t count(glm::uvec3 d) { return std::size_t(d.x) * d.y * d.z; }

// One 1D pass: which level it belongs to, its axis, and its input and output dims.
struct PassShape {
  int level;  // reads level `level` (or its partial results), writes towards level + 1
  int axis;
  glm::uvec3 src, dst;
};

std::vector<PassShape> pass_shapes(const std::vector<glm::uvec3>& level_dims) {
  std::vector<PassShape> passes;
  for (int l = 0; l + 1 < int(level_dims.size()); ++l) {
    glm::uvec3 d = level_dims[l];
    for (int axis = 0; axis < 3; ++axis) {
      glm::uvec3 next = d;
      next[axis] = (d[axis] + 1) / 2;
      passes.push_back({l, axis, d, next});
      d = next;
    }
  }
  return passes;
}

// A pass dispatches one row of workgroups per z plane of its output (see the shader).
std::uint32_t plane_groups(glm::uvec3 d) {
  return std::uint32_t((std::size_t(d.x) * d.y + FRACREF_WORKGROUP - 1) / FRACREF_WORKGROUP);
}

void check_limits(const VulkanContext& context, glm::uvec3 dims) {
  const VkPhysicalDeviceLimits& lim = context.limits();
  const std::size_t elements = count(dims);
  const std::size_t widest = std::size_t((dims.x + 1) / 2) * dims.y;  // the x pass of level 0
  if (elements > lim.maxTexelBufferElements || elements * sizeof(float) > lim.maxStorageBufferRange ||
      (widest + FRACREF_WORKGROUP - 1) / FRACREF_WORKGROUP > lim.maxComputeWorkGroupCount[0] ||
      dims.z > lim.maxComputeWorkGroupCount[1]) {
    throw RunError("a " + std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) +
                   " pyramid base exceeds the limits of " + context.describe() + " (maxTexelBufferElements " +
                   std::to_string(lim.maxTexelBufferElements) + ", maxStorageBufferRange " +
                   std::to_string(lim.maxStorageBufferRange) + " bytes, maxComputeWorkGroupCount " +
                   std::to_string(lim.maxComputeWorkGroupCount[0]) + "x" +
                   std::to_string(lim.maxComputeWorkGroupCount[1]) + "): use the CPU backend");
  }
}

void compute_barrier(VkCommandBuffer cb, VkAccessFlags dst_access, VkPipelineStageFlags dst_stage) {
  auto barrier = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, dst_stage, 0, 1, &barrier, 0, nullptr, 0,
                       nullptr);
}

}  // namespace

VulkanPyramid::VulkanPyramid(VulkanContext& context, const PyramidOptions& options) : context_(context) {
  set_options(options);
  blur_ = std::make_unique<ComputePipeline>(
      context, std::span<const std::uint32_t>(pyramid_blur_spv),
      std::vector{BindingType::UniformTexelBuffer, BindingType::StorageBuffer, BindingType::UniformBuffer},
      std::uint32_t(sizeof(gpu::BlurParams)));
  weights_ = VulkanBuffer(context, sizeof(gpu::BlurWeights), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);

  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, kMaxPasses},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kMaxPasses},
                                        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kMaxPasses}};
  auto pool = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool.maxSets = kMaxPasses;
  pool.poolSizeCount = 3;
  pool.pPoolSizes = sizes;
  vk_check(vkCreateDescriptorPool(context.device(), &pool, nullptr, &pool_), "vkCreateDescriptorPool");

  auto alloc = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = context.command_pool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  const VkResult r = vkAllocateCommandBuffers(context.device(), &alloc, &commands_);
  if (r != VK_SUCCESS) {
    vkDestroyDescriptorPool(context.device(), pool_, nullptr);
    vk_check(r, "vkAllocateCommandBuffers");
  }
}

VulkanPyramid::~VulkanPyramid() {
  destroy_views();
  vkFreeCommandBuffers(context_.device(), context_.command_pool(), 1, &commands_);
  vkDestroyDescriptorPool(context_.device(), pool_, nullptr);
}

void VulkanPyramid::set_options(const PyramidOptions& options) {
  Grid3 probe;
  probe.dims = {1, 1, 1};
  probe.values = {0.0f};
  check_pyramid_input(probe, options);
  options_ = options;
}

void VulkanPyramid::prepare(glm::uvec3 dims) {
  if (dims == recorded_dims_ && options_.levels == recorded_options_.levels &&
      options_.sigma == recorded_options_.sigma) {
    return;
  }
  if (dims.x < 1 || dims.y < 1 || dims.z < 1) throw InputError("pyramid: grid dims must all be >= 1");
  check_limits(context_, dims);
  // Forget the old recording first: if anything below throws, no stale replay can follow.
  recorded_dims_ = {0, 0, 0};
  built_ = false;
  const std::vector<glm::uvec3> level_dims = pyramid_level_dims(dims, options_.levels);
  allocate(level_dims);
  write_descriptors(level_dims);
  record(level_dims);
  recorded_dims_ = dims;
  recorded_options_ = options_;
  ++record_count_;
}

std::vector<Grid3> VulkanPyramid::build(const Grid3& base) {
  check_pyramid_input(base, options_);
  prepare(base.dims);
  std::memcpy(levels_[0].data(), base.values.data(), base.values.size() * sizeof(float));
  if (options_.levels > 1) context_.submit_and_wait(commands_);
  built_ = true;
  std::vector<Grid3> out{base};
  for (int l = 1; l < options_.levels; ++l) {
    Grid3 level;
    level.dims = (out.back().dims + 1u) / 2u;
    level.origin = base.origin;
    level.cell = out.back().cell * 2.0;
    const float* data = levels_[l].as<const float>();
    level.values.assign(data, data + level.size());
    out.push_back(std::move(level));
  }
  return out;
}

void VulkanPyramid::allocate(const std::vector<glm::uvec3>& dims) {
  levels_.resize(dims.size());
  for (std::size_t l = 0; l < dims.size(); ++l) {
    const VkDeviceSize bytes = count(dims[l]) * sizeof(float);
    if (!levels_[l]) levels_[l] = VulkanBuffer(context_, bytes, kGridUsage);
    levels_[l].grow(bytes);
  }
  const std::vector<PassShape> passes = pass_shapes(dims);
  for (VulkanBuffer* scratch : {&after_x_, &after_y_}) {
    const int axis = scratch == &after_x_ ? 0 : 1;
    std::size_t most = 1;
    for (const PassShape& p : passes) most = p.axis == axis ? std::max(most, count(p.dst)) : most;
    if (!*scratch) *scratch = VulkanBuffer(context_, most * sizeof(float), kGridUsage);
    scratch->grow(most * sizeof(float));
  }
  gpu::BlurWeights table{};
  const std::vector<float> w = gaussian_weights(options_.sigma);
  for (std::size_t j = 0; j < w.size(); ++j) table.w[j / 4][j % 4] = w[j];
  std::memcpy(weights_.data(), &table, sizeof(table));
}

void VulkanPyramid::write_descriptors(const std::vector<glm::uvec3>& dims) {
  destroy_views();
  vk_check(vkResetDescriptorPool(context_.device(), pool_, 0), "vkResetDescriptorPool");
  const std::vector<PassShape> passes = pass_shapes(dims);
  sets_.clear();
  if (passes.empty()) return;  // a one-level pyramid runs no pass
  const std::vector<VkDescriptorSetLayout> layouts(passes.size(), blur_->set_layout());
  sets_.resize(passes.size());
  auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = pool_;
  alloc.descriptorSetCount = std::uint32_t(passes.size());
  alloc.pSetLayouts = layouts.data();
  vk_check(vkAllocateDescriptorSets(context_.device(), &alloc, sets_.data()), "vkAllocateDescriptorSets");

  const VulkanBuffer* inputs[] = {nullptr, &after_x_, &after_y_};
  const VulkanBuffer* outputs[] = {&after_x_, &after_y_, nullptr};
  for (std::size_t i = 0; i < passes.size(); ++i) {
    const PassShape& p = passes[i];
    const VulkanBuffer& in = p.axis == 0 ? levels_[p.level] : *inputs[p.axis];
    const VulkanBuffer& out = p.axis == 2 ? levels_[p.level + 1] : *outputs[p.axis];
    auto view = vk_struct<VkBufferViewCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO);
    view.buffer = in.handle();
    view.format = VK_FORMAT_R32_SFLOAT;
    view.range = count(p.src) * sizeof(float);
    views_.push_back(VK_NULL_HANDLE);
    vk_check(vkCreateBufferView(context_.device(), &view, nullptr, &views_.back()), "vkCreateBufferView");
    const VkDescriptorBufferInfo dst{out.handle(), 0, count(p.dst) * sizeof(float)};
    const VkDescriptorBufferInfo table{weights_.handle(), 0, sizeof(gpu::BlurWeights)};
    VkWriteDescriptorSet writes[3];
    for (std::uint32_t b = 0; b < 3; ++b) {
      writes[b] = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      writes[b].dstSet = sets_[i];
      writes[b].dstBinding = b;
      writes[b].descriptorCount = 1;
      writes[b].descriptorType = descriptor_type(blur_->bindings()[b]);
    }
    writes[0].pTexelBufferView = &views_.back();
    writes[1].pBufferInfo = &dst;
    writes[2].pBufferInfo = &table;
    vkUpdateDescriptorSets(context_.device(), 3, writes, 0, nullptr);
  }
}

void VulkanPyramid::record(const std::vector<glm::uvec3>& dims) {
  vk_check(vkResetCommandBuffer(commands_, 0), "vkResetCommandBuffer");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  vk_check(vkBeginCommandBuffer(commands_, &begin), "vkBeginCommandBuffer");
  vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, blur_->handle());
  const std::vector<PassShape> passes = pass_shapes(dims);
  const std::uint32_t radius = std::uint32_t(gaussian_weights(options_.sigma).size() / 2);
  for (std::size_t i = 0; i < passes.size(); ++i) {
    const PassShape& p = passes[i];
    const gpu::BlurParams params{{p.src, std::uint32_t(p.axis)}, {p.dst, radius}};
    vkCmdBindDescriptorSets(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, blur_->layout(), 0, 1, &sets_[i], 0,
                            nullptr);
    vkCmdPushConstants(commands_, blur_->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(params), &params);
    vkCmdDispatch(commands_, plane_groups(p.dst), p.dst.z, 1);
    const bool last = i + 1 == passes.size();
    compute_barrier(commands_, last ? VK_ACCESS_HOST_READ_BIT : VK_ACCESS_SHADER_READ_BIT,
                    last ? VK_PIPELINE_STAGE_HOST_BIT : VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  }
  vk_check(vkEndCommandBuffer(commands_), "vkEndCommandBuffer");
}

const VulkanBuffer& VulkanPyramid::level_buffer(int level) const {
  if (!built_ || level < 0 || level >= recorded_options_.levels) {
    throw RunError("VulkanPyramid::level_buffer(" + std::to_string(level) + "): no such level has been built");
  }
  return levels_[level];
}

void VulkanPyramid::destroy_views() noexcept {
  for (VkBufferView v : views_) vkDestroyBufferView(context_.device(), v, nullptr);
  views_.clear();
}

}  // namespace fracref
