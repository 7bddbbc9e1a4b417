#include "vk_backend.hpp"

#include <cstring>
#include <optional>

#include "layout.h"
#include "spv/flow_sample_spv.h"
#include "spv/flow_samples_spv.h"
#include "spv/flow_velocity_spv.h"
#include "util/error.hpp"
#include "vk_flow_kernel.hpp"
#include "vk_pyramid.hpp"

namespace fracref {
namespace {

constexpr VkBufferUsageFlags kTexel = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr BindingType kT = BindingType::UniformTexelBuffer;
constexpr BindingType kS = BindingType::StorageBuffer;
constexpr BindingType kU = BindingType::UniformBuffer;

// Offsets of the two VkDispatchIndirectCommand in the indirect buffer.
constexpr VkDeviceSize kVertexDispatch = 0, kSampleDispatch = sizeof(VkDispatchIndirectCommand);

// Returns `context` once it is known to read every format the kernels use as texel buffers
// (called before the arrays are created, so the error is this one and not a Vulkan failure).
VulkanContext& check_formats(VulkanContext& context) {
  const std::pair<VkFormat, const char*> formats[] = {{VK_FORMAT_R32G32B32A32_SFLOAT, "R32G32B32A32_SFLOAT"},
                                                      {VK_FORMAT_R32G32B32A32_UINT, "R32G32B32A32_UINT"},
                                                      {VK_FORMAT_R32G32_UINT, "R32G32_UINT"},
                                                      {VK_FORMAT_R32_UINT, "R32_UINT"}};
  for (const auto& [format, name] : formats) {
    VkFormatProperties props;
    vkGetPhysicalDeviceFormatProperties(context.physical_device(), format, &props);
    if (!(props.bufferFeatures & VK_FORMAT_FEATURE_UNIFORM_TEXEL_BUFFER_BIT)) {
      throw RunError("vulkan backend: " + context.describe() + " cannot read " + name +
                     " as a uniform texel buffer: use the CPU backend");
    }
  }
  return context;
}

void require(bool ok, const char* call, const std::string& what) {
  if (!ok) throw RunError(std::string("VulkanBackend::") + call + ": " + what);
}

// The shape of a CSR: offsets non-decreasing from 0 to `entries`.
bool csr_shape_ok(std::span<const std::uint32_t> offsets, std::size_t entries) {
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != entries) return false;
  for (std::size_t i = 1; i < offsets.size(); ++i)
    if (offsets[i] < offsets[i - 1]) return false;
  return true;
}

bool ids_below(std::span<const std::uint32_t> ids, std::size_t n) {
  for (std::uint32_t id : ids)
    if (id >= n) return false;
  return true;
}

bool corners_below(std::span<const glm::uvec4> faces, std::size_t n) {
  for (const glm::uvec4& f : faces)
    if (f.x >= n || f.y >= n || f.z >= n) return false;
  return true;
}

bool pairs_below(std::span<const glm::uvec2> pairs, std::size_t n) {
  for (const glm::uvec2& p : pairs)
    if (p.x >= n || p.y >= n) return false;
  return true;
}

VkCommandBuffer allocate_commands(VulkanContext& context) {
  auto alloc = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = context.command_pool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  vk_check(vkAllocateCommandBuffers(context.device(), &alloc, &cb), "vkAllocateCommandBuffers");
  return cb;
}

}  // namespace

struct VulkanBackend::Impl {
  explicit Impl(VulkanContext& context);
  ~Impl();

  void release() noexcept;
  VkDescriptorPool create_pool();
  void set_field(const FieldGrid4& field);
  void upload_topology(const SurfaceView& s);
  void upload_fans(const SampleView& samples, std::size_t vertices);
  void set_dispatch(VkDeviceSize offset, std::size_t elements);
  void record_vertex_commands();
  void record_sample_commands();
  void vertex_velocities(const SurfaceView& s, std::span<glm::vec4> samples, std::span<glm::vec4> velocity);
  void sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                    const SampleView& samples, std::span<glm::vec4> out);

  VulkanContext& context;
  VulkanBackendStats stats;
  std::optional<VulkanPyramid> pyramid;
  bool field_set = false;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkCommandBuffer vertex_commands = VK_NULL_HANDLE, sample_commands = VK_NULL_HANDLE;
  bool vertex_recorded = false, sample_recorded = false;
  // The resident arrays, in the order the kernels bind them.
  DeviceArray field{context, "field grid nodes", VK_FORMAT_R32G32B32A32_SFLOAT, 16, kTexel};
  DeviceArray positions{context, "positions", VK_FORMAT_R32G32B32A32_SFLOAT, 16, kTexel};
  DeviceArray faces{context, "faces", VK_FORMAT_R32G32B32A32_UINT, 16, kTexel};
  DeviceArray vf_offsets{context, "vertex-face offsets", VK_FORMAT_R32_UINT, 4, kTexel};
  DeviceArray vf_faces{context, "vertex-face entries", VK_FORMAT_R32_UINT, 4, kTexel};
  DeviceArray samples{context, "vertex samples", VK_FORMAT_R32G32B32A32_SFLOAT, 16, kTexel | kStorage};
  DeviceArray velocity{context, "velocities", VK_FORMAT_UNDEFINED, 16, kStorage};
  DeviceArray points{context, "sample points", VK_FORMAT_R32G32B32A32_SFLOAT, 16, kTexel};
  DeviceArray fan_offsets{context, "fan offsets", VK_FORMAT_R32_UINT, 4, kTexel};
  DeviceArray fan_pairs{context, "fan pairs", VK_FORMAT_R32G32_UINT, 8, kTexel};
  DeviceArray results{context, "sample results", VK_FORMAT_UNDEFINED, 16, kStorage};
  DeviceArray params{context, "parameters", VK_FORMAT_UNDEFINED, sizeof(gpu::FlowParams),
                     VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT};
  DeviceArray indirect{context, "dispatches", VK_FORMAT_UNDEFINED, sizeof(VkDispatchIndirectCommand),
                       VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT};
  std::unique_ptr<FlowKernel> k1, k2, k3;
};

VulkanBackend::Impl::Impl(VulkanContext& ctx) : context(check_formats(ctx)) {
  indirect.reserve(2);
  std::memset(params.data(), 0, sizeof(gpu::FlowParams));
  pool = create_pool();
  try {
    k1 = std::make_unique<FlowKernel>(context, flow_sample_spv, std::vector{kT, kT, kS, kU},
                                      std::vector<const DeviceArray*>{&field, &positions, &samples, &params}, pool);
    k2 = std::make_unique<FlowKernel>(
        context, flow_velocity_spv, std::vector{kT, kT, kT, kT, kT, kS, kU},
        std::vector<const DeviceArray*>{&positions, &faces, &vf_offsets, &vf_faces, &samples, &velocity, &params},
        pool);
    k3 = std::make_unique<FlowKernel>(context, flow_samples_spv, std::vector{kT, kT, kT, kT, kT, kT, kS, kU},
                                      std::vector<const DeviceArray*>{&field, &positions, &samples, &points,
                                                                      &fan_offsets, &fan_pairs, &results, &params},
                                      pool);
    vertex_commands = allocate_commands(context);
    sample_commands = allocate_commands(context);
  } catch (...) {
    release();  // a constructor that throws gets no destructor call (its members' do run)
    throw;
  }
}

VulkanBackend::Impl::~Impl() { release(); }

void VulkanBackend::Impl::release() noexcept {
  for (VkCommandBuffer* cb : {&vertex_commands, &sample_commands}) {
    if (*cb) vkFreeCommandBuffers(context.device(), context.command_pool(), 1, cb);
    *cb = VK_NULL_HANDLE;
  }
  if (pool) vkDestroyDescriptorPool(context.device(), pool, nullptr);
  pool = VK_NULL_HANDLE;
}

VkDescriptorPool VulkanBackend::Impl::create_pool() {
  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 13},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3},
                                        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 3}};
  auto info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  info.maxSets = 3;
  info.poolSizeCount = 3;
  info.pPoolSizes = sizes;
  VkDescriptorPool p = VK_NULL_HANDLE;
  vk_check(vkCreateDescriptorPool(context.device(), &info, nullptr, &p), "vkCreateDescriptorPool");
  return p;
}

void VulkanBackend::Impl::set_field(const FieldGrid4& f) {
  require(f.dims.x >= 2 && f.dims.y >= 2 && f.dims.z >= 2, "set_field", "field grid dims must all be >= 2");
  require(f.values.size() == std::size_t(f.dims.x) * f.dims.y * f.dims.z, "set_field",
          "field grid holds " + std::to_string(f.values.size()) + " values for " + std::to_string(f.dims.x) + "x" +
              std::to_string(f.dims.y) + "x" + std::to_string(f.dims.z) + " nodes");
  field.upload(f.values.data(), f.values.size() * sizeof(glm::vec4));
  auto* p = static_cast<gpu::FlowParams*>(params.data());
  // The same float conversions as sample_field.
  p->field_dims = glm::uvec4(f.dims, 0u);
  p->field_origin = glm::vec4(glm::vec3(f.origin), float(f.cell));
  field_set = true;
}

// Uploads what changed and, when anything did, checks the indices the shader will follow
// (an index out of range would read outside a buffer on the device).
void VulkanBackend::Impl::upload_topology(const SurfaceView& s) {
  bool changed = faces.upload_if_changed(s.faces.data(), s.faces.size_bytes());
  changed |= vf_offsets.upload_if_changed(s.vf_offsets.data(), s.vf_offsets.size_bytes());
  changed |= vf_faces.upload_if_changed(s.vf_faces.data(), s.vf_faces.size_bytes());
  if (!changed) return;
  ++stats.topology_uploads;
  const std::size_t n = s.positions.size();
  try {
    require(csr_shape_ok(s.vf_offsets, s.vf_faces.size()), "vertex_velocities",
            "vf_offsets is not a CSR of vf_faces (must rise from 0 to vf_faces.size())");
    require(ids_below(s.vf_faces, s.faces.size()), "vertex_velocities", "a vf_faces entry is not a face id");
    require(corners_below(s.faces, n), "vertex_velocities", "a face corner is not a vertex id");
  } catch (...) {
    faces.forget_shadow();  // the next call uploads and checks again
    throw;
  }
}

void VulkanBackend::Impl::upload_fans(const SampleView& s, std::size_t vertices) {
  require(csr_shape_ok(s.fan_offsets, s.fan_pairs.size()), "sample_tests",
          "fan_offsets is not a CSR of fan_pairs (must rise from 0 to fan_pairs.size())");
  require(pairs_below(s.fan_pairs, vertices), "sample_tests", "a fan pair names no vertex");
  points.upload(s.points.data(), s.points.size_bytes());
  fan_offsets.upload(s.fan_offsets.data(), s.fan_offsets.size_bytes());
  fan_pairs.upload(s.fan_pairs.data(), s.fan_pairs.size_bytes());
}

void VulkanBackend::Impl::set_dispatch(VkDeviceSize offset, std::size_t elements) {
  const std::size_t groups = (elements + FRACREF_WORKGROUP - 1) / FRACREF_WORKGROUP;
  const std::uint32_t most = context.limits().maxComputeWorkGroupCount[0];
  if (groups > most) {
    throw RunError("vulkan backend: " + std::to_string(elements) + " elements need " + std::to_string(groups) +
                   " workgroups, more than maxComputeWorkGroupCount.x = " + std::to_string(most) + " of " +
                   context.describe() + ": use the CPU backend");
  }
  auto* cmd = reinterpret_cast<VkDispatchIndirectCommand*>(static_cast<char*>(indirect.data()) + offset);
  *cmd = {std::uint32_t(groups), 1, 1};
}

void VulkanBackend::Impl::record_vertex_commands() {
  const bool moved = k1->refresh() | k2->refresh();
  if (vertex_recorded && !moved) return;
  vertex_recorded = false;
  vk_check(vkResetCommandBuffer(vertex_commands, 0), "vkResetCommandBuffer");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  vk_check(vkBeginCommandBuffer(vertex_commands, &begin), "vkBeginCommandBuffer");
  k1->record_dispatch(vertex_commands, indirect.handle(), kVertexDispatch);
  flow_barrier(vertex_commands, VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  k2->record_dispatch(vertex_commands, indirect.handle(), kVertexDispatch);
  flow_barrier(vertex_commands, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
  vk_check(vkEndCommandBuffer(vertex_commands), "vkEndCommandBuffer");
  vertex_recorded = true;
  ++stats.records;
}

void VulkanBackend::Impl::record_sample_commands() {
  const bool moved = k3->refresh();
  if (sample_recorded && !moved) return;
  sample_recorded = false;
  vk_check(vkResetCommandBuffer(sample_commands, 0), "vkResetCommandBuffer");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  vk_check(vkBeginCommandBuffer(sample_commands, &begin), "vkBeginCommandBuffer");
  k3->record_dispatch(sample_commands, indirect.handle(), kSampleDispatch);
  flow_barrier(sample_commands, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
  vk_check(vkEndCommandBuffer(sample_commands), "vkEndCommandBuffer");
  sample_recorded = true;
  ++stats.records;
}

void VulkanBackend::Impl::vertex_velocities(const SurfaceView& s, std::span<glm::vec4> out_samples,
                                            std::span<glm::vec4> out_velocity) {
  const std::size_t n = s.positions.size();
  require(field_set, "vertex_velocities", "set_field was not called");
  require(out_samples.size() == n && out_velocity.size() == n, "vertex_velocities",
          "samples and velocity must have one entry per vertex");
  require(s.vf_offsets.size() == n + 1, "vertex_velocities", "vf_offsets must have vertices + 1 entries");
  upload_topology(s);
  if (n == 0) return;
  set_dispatch(kVertexDispatch, n);
  positions.upload(s.positions.data(), s.positions.size_bytes());
  samples.reserve(n);
  velocity.reserve(n);
  static_cast<gpu::FlowParams*>(params.data())->counts.x = std::uint32_t(n);
  record_vertex_commands();
  context.submit_and_wait(vertex_commands);
  ++stats.submits;
  std::memcpy(out_samples.data(), samples.data(), n * sizeof(glm::vec4));
  std::memcpy(out_velocity.data(), velocity.data(), n * sizeof(glm::vec4));
}

void VulkanBackend::Impl::sample_tests(std::span<const glm::vec4> pos, std::span<const glm::vec4> vertex_samples,
                                       const SampleView& s, std::span<glm::vec4> out) {
  const std::size_t m = s.points.size();
  require(field_set, "sample_tests", "set_field was not called");
  require(vertex_samples.size() == pos.size(), "sample_tests", "vertex_samples must have one entry per vertex");
  require(out.size() == m, "sample_tests", "out must have one entry per sample point");
  require(s.fan_offsets.size() == m + 1, "sample_tests", "fan_offsets must have points + 1 entries");
  if (m == 0) return;
  upload_fans(s, pos.size());
  set_dispatch(kSampleDispatch, m);
  positions.upload(pos.data(), pos.size_bytes());
  samples.upload(vertex_samples.data(), vertex_samples.size_bytes());
  results.reserve(m);
  static_cast<gpu::FlowParams*>(params.data())->counts.y = std::uint32_t(m);
  record_sample_commands();
  context.submit_and_wait(sample_commands);
  ++stats.submits;
  std::memcpy(out.data(), results.data(), m * sizeof(glm::vec4));
}

VulkanBackend::VulkanBackend(VulkanContext& context) : impl_(std::make_unique<Impl>(context)) {}

VulkanBackend::VulkanBackend(const VulkanContextOptions& options) {
  try {
    owned_ = std::make_unique<VulkanContext>(options);
  } catch (const RunError& e) {
    throw RunError(std::string("vulkan backend: ") + e.what());
  }
  impl_ = std::make_unique<Impl>(*owned_);
}

VulkanBackend::~VulkanBackend() = default;

std::string VulkanBackend::name() const {
  return std::string("vulkan (") + impl_->context.properties().deviceName + ")";
}

std::vector<Grid3> VulkanBackend::build_pyramid(const Grid3& base, const PyramidOptions& options) {
  if (!impl_->pyramid) impl_->pyramid.emplace(impl_->context, options);
  impl_->pyramid->set_options(options);
  return impl_->pyramid->build(base);
}

void VulkanBackend::set_field(const FieldGrid4& field) { impl_->set_field(field); }

void VulkanBackend::vertex_velocities(const SurfaceView& surface, std::span<glm::vec4> samples,
                                      std::span<glm::vec4> velocity) {
  impl_->vertex_velocities(surface, samples, velocity);
}

void VulkanBackend::sample_tests(std::span<const glm::vec4> positions, std::span<const glm::vec4> vertex_samples,
                                 const SampleView& samples, std::span<glm::vec4> out) {
  impl_->sample_tests(positions, vertex_samples, samples, out);
}

const VulkanBackendStats& VulkanBackend::stats() const { return impl_->stats; }

VulkanContext& VulkanBackend::context() { return impl_->context; }

std::unique_ptr<ComputeBackend> make_vulkan_backend(VulkanContext& context) {
  return std::make_unique<VulkanBackend>(context);
}

std::unique_ptr<ComputeBackend> make_vulkan_backend(const VulkanContextOptions& options) {
  return std::make_unique<VulkanBackend>(options);
}

}  // namespace fracref
