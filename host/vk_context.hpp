#pragma once
// The Vulkan context every kernel runs in: instance, one physical device, a logical device with
// one compute queue, a command pool and a pipeline cache; plus the validation-layer hook.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace fracref {

struct VulkanContextOptions {
  /// Enable the Khronos validation layer (also when env FRACREF_VK_VALIDATION=1) if installed;
  /// synchronization validation is enabled with it.
  bool validation = false;
  /// Rank devices discrete > integrated > virtual > CPU; false takes the first usable device
  /// in the loader's order.
  bool prefer_discrete = true;
};

/// What device selection knows about one physical device (kept apart from Vulkan handles so
/// the selection rule can be tested without the hardware).
struct DeviceCandidate {
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::uint32_t api_version = 0;
  bool compute_queue = false;         ///< some queue family supports VK_QUEUE_COMPUTE_BIT
  bool texel_buffer_formats = false;  ///< R32_SFLOAT usable as uniform texel buffer
  std::uint32_t max_workgroup_x = 0;  ///< maxComputeWorkGroupSize[0]
};

/// Why `c` cannot run fracref's kernels, or "" when it can.
std::string device_rejection(const DeviceCandidate& c);

/// Index of the device to use: the best-ranked usable one (ties: the first).
/// \throw RunError listing every device with the reason it was rejected, or saying that no
///        Vulkan driver is installed when `candidates` is empty.
std::size_t select_device(const std::vector<DeviceCandidate>& candidates, bool prefer_discrete);

/// "discrete GPU", "integrated GPU", "virtual GPU", "CPU" or "other".
const char* device_type_name(VkPhysicalDeviceType type);

/// A zero-initialised Vulkan struct with its sType set.
template <class T>
T vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

/// Throws RunError("<what> failed: VK_ERROR_...") unless `result` is VK_SUCCESS.
void vk_check(VkResult result, const char* what);

/// Instance, device, compute queue, command pool and pipeline cache. Neither copyable nor
/// movable (buffers and pipelines keep a reference); not thread-safe: use it from one thread.
class VulkanContext {
 public:
  /// \throw RunError when no usable device exists (the message lists every device and why it was
  ///        rejected) or when the instance or device cannot be created.
  explicit VulkanContext(const VulkanContextOptions& options = {});
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  VkCommandPool command_pool() const { return command_pool_; }
  VkPipelineCache pipeline_cache() const { return pipeline_cache_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }

  /// e.g. "llvmpipe (LLVM 15.0.6, 256 bits) [CPU, llvmpipe Mesa 22.3.6, Vulkan 1.3.230]".
  std::string describe() const;

  /// Index of a memory type allowed by `type_bits` with all of `required`, preferring one that
  /// also has all of `preferred`. \throw RunError when none has `required`.
  std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred = 0) const;

  /// Submits `commands` to the compute queue and blocks until it has finished.
  /// \throw RunError on failure (e.g. VK_ERROR_DEVICE_LOST).
  void submit_and_wait(VkCommandBuffer commands);

  /// True when the validation layer is active in this context.
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  /// Warnings and errors the validation layer reported so far, "severity: message" each.
  std::vector<std::string> validation_messages() const;
  void clear_validation_messages();

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* self);
  void create_instance(bool validation);
  void pick_physical_device(bool prefer_discrete);
  void create_device();
  void release();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  std::string driver_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkPipelineCache pipeline_cache_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

/// Whether a usable Vulkan device exists; when not, `*why` (if given) says why. The answer is
/// computed once per process (it creates and destroys a context).
bool vulkan_available(std::string* why = nullptr);

}  // namespace fracref
