#include "vk_context.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "layout.h"
#include "util/error.hpp"

namespace fracref {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr const char* kNoDriver = "no Vulkan driver found: install mesa-vulkan-drivers for lavapipe";
constexpr std::uint32_t kMinApi = VK_API_VERSION_1_1;  // the shaders target SPIR-V for Vulkan 1.1

const char* result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default: return "unknown VkResult";
  }
}

std::string version_string(std::uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

template <class T, class F>
std::vector<T> enumerate(F&& call) {
  std::uint32_t n = 0;
  call(&n, static_cast<T*>(nullptr));
  std::vector<T> out(n);
  call(&n, out.data());
  out.resize(n);
  return out;
}

bool has_extension(const std::vector<VkExtensionProperties>& list, const char* name) {
  return std::any_of(list.begin(), list.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

bool has_layer(const char* name) {
  auto layers = enumerate<VkLayerProperties>([](std::uint32_t* n, VkLayerProperties* p) {
    return vkEnumerateInstanceLayerProperties(n, p);
  });
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

std::vector<VkExtensionProperties> instance_extensions(const char* layer) {
  return enumerate<VkExtensionProperties>([layer](std::uint32_t* n, VkExtensionProperties* p) {
    return vkEnumerateInstanceExtensionProperties(layer, n, p);
  });
}

// The instance layers and extensions to enable: portability enumeration where the loader has
// it (MoltenVK), and the validation layer with debug utils (and synchronization validation)
// when asked for and installed.
struct InstanceSetup {
  std::vector<const char*> layers, extensions;
  bool portability = false, sync_validation = false;
};

InstanceSetup instance_setup(bool validation) {
  InstanceSetup s;
  const auto available = instance_extensions(nullptr);
  s.portability = has_extension(available, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
  if (s.portability) s.extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
  if (!validation || !has_layer(kValidationLayer)) return s;
  const auto layer_ext = instance_extensions(kValidationLayer);
  if (!has_extension(available, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) &&
      !has_extension(layer_ext, VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) {
    return s;
  }
  s.layers.push_back(kValidationLayer);
  s.extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  s.sync_validation = has_extension(layer_ext, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  if (s.sync_validation) s.extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  return s;
}

DeviceCandidate describe_candidate(VkPhysicalDevice pd) {
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(pd, &props);
  DeviceCandidate c;
  c.name = props.deviceName;
  c.type = props.deviceType;
  c.api_version = props.apiVersion;
  c.max_workgroup_x = props.limits.maxComputeWorkGroupSize[0];
  auto families = enumerate<VkQueueFamilyProperties>([pd](std::uint32_t* n, VkQueueFamilyProperties* p) {
    vkGetPhysicalDeviceQueueFamilyProperties(pd, n, p);
    return VK_SUCCESS;
  });
  for (const auto& f : families) c.compute_queue |= (f.queueFlags & VK_QUEUE_COMPUTE_BIT) && f.queueCount > 0;
  VkFormatProperties fmt;
  vkGetPhysicalDeviceFormatProperties(pd, VK_FORMAT_R32_SFLOAT, &fmt);
  c.texel_buffer_formats = fmt.bufferFeatures & VK_FORMAT_FEATURE_UNIFORM_TEXEL_BUFFER_BIT;
  return c;
}

}  // namespace

void vk_check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) {
    throw RunError(std::string(what) + " failed: " + result_name(result) + " (" + std::to_string(result) + ")");
  }
}

const char* device_type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

std::string device_rejection(const DeviceCandidate& c) {
  if (c.api_version < kMinApi) return "supports Vulkan " + version_string(c.api_version) + ", fracref needs 1.1";
  if (!c.compute_queue) return "no queue family supports compute";
  if (!c.texel_buffer_formats) return "R32_SFLOAT cannot be read as a uniform texel buffer";
  if (c.max_workgroup_x < FRACREF_WORKGROUP) {
    return "maxComputeWorkGroupSize.x is " + std::to_string(c.max_workgroup_x) + ", fracref needs " +
           std::to_string(FRACREF_WORKGROUP);
  }
  return "";
}

std::size_t select_device(const std::vector<DeviceCandidate>& candidates, bool prefer_discrete) {
  if (candidates.empty()) throw RunError(kNoDriver);
  std::size_t best = candidates.size();
  std::string reasons;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const DeviceCandidate& c = candidates[i];
    const std::string why = device_rejection(c);
    if (!why.empty()) {
      reasons += "\n  [" + std::to_string(i) + "] " + c.name + " (" + device_type_name(c.type) + "): " + why;
    } else if (best == candidates.size() ||
               (prefer_discrete && type_rank(c.type) > type_rank(candidates[best].type))) {
      best = i;
    }
  }
  if (best == candidates.size()) {
    throw RunError("no usable Vulkan device among " + std::to_string(candidates.size()) + ":" + reasons);
  }
  return best;
}

VulkanContext::VulkanContext(const VulkanContextOptions& options) {
  try {
    create_instance(options.validation || env_flag("FRACREF_VK_VALIDATION"));
    pick_physical_device(options.prefer_discrete);
    create_device();
  } catch (...) {
    release();  // a constructor that throws gets no destructor call
    throw;
  }
}

VulkanContext::~VulkanContext() { release(); }

void VulkanContext::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (fence_) vkDestroyFence(device_, fence_, nullptr);
    if (pipeline_cache_) vkDestroyPipelineCache(device_, pipeline_cache_, nullptr);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
}

void VulkanContext::create_instance(bool validation) {
  const InstanceSetup setup = instance_setup(validation);
  const std::vector<const char*>& layers = setup.layers;
  auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "fracref";
  app.pEngineName = "fracref";
  app.apiVersion = kMinApi;

  auto messenger = vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  messenger.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &VulkanContext::on_message;
  messenger.pUserData = this;
  const VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  auto features = vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  if (setup.sync_validation) messenger.pNext = &features;

  auto info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  info.enabledLayerCount = std::uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = std::uint32_t(setup.extensions.size());
  info.ppEnabledExtensionNames = setup.extensions.data();
  if (setup.portability) info.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  if (!layers.empty()) info.pNext = &messenger;
  const VkResult r = vkCreateInstance(&info, nullptr, &instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) throw RunError(kNoDriver);
  vk_check(r, "vkCreateInstance");

  if (!layers.empty()) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    messenger.pNext = nullptr;
    if (!create) throw RunError("vkCreateDebugUtilsMessengerEXT is missing although VK_EXT_debug_utils is enabled");
    vk_check(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
}

void VulkanContext::pick_physical_device(bool prefer_discrete) {
  auto devices = enumerate<VkPhysicalDevice>([this](std::uint32_t* n, VkPhysicalDevice* p) {
    return vkEnumeratePhysicalDevices(instance_, n, p);
  });
  std::vector<DeviceCandidate> candidates;
  for (VkPhysicalDevice pd : devices) candidates.push_back(describe_candidate(pd));
  physical_ = devices[select_device(candidates, prefer_discrete)];
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  if (properties_.apiVersion >= VK_API_VERSION_1_2) {
    auto driver = vk_struct<VkPhysicalDeviceDriverProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    auto props2 = vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    props2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical_, &props2);
    driver_ = std::string(driver.driverName) + " " + driver.driverInfo;
  }
}

void VulkanContext::create_device() {
  auto families = enumerate<VkQueueFamilyProperties>([this](std::uint32_t* n, VkQueueFamilyProperties* p) {
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, n, p);
    return VK_SUCCESS;
  });
  for (queue_family_ = 0; queue_family_ < families.size(); ++queue_family_) {
    if ((families[queue_family_].queueFlags & VK_QUEUE_COMPUTE_BIT) && families[queue_family_].queueCount > 0) break;
  }
  const float priority = 1.0f;
  auto queue = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  // A portability (non-conformant) implementation requires its subset extension to be enabled.
  const auto device_ext = enumerate<VkExtensionProperties>([this](std::uint32_t* n, VkExtensionProperties* p) {
    return vkEnumerateDeviceExtensionProperties(physical_, nullptr, n, p);
  });
  std::vector<const char*> extensions;
  if (has_extension(device_ext, "VK_KHR_portability_subset")) extensions.push_back("VK_KHR_portability_subset");
  auto info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = std::uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  vk_check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  auto pool = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = queue_family_;
  vk_check(vkCreateCommandPool(device_, &pool, nullptr, &command_pool_), "vkCreateCommandPool");
  auto cache = vk_struct<VkPipelineCacheCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO);
  vk_check(vkCreatePipelineCache(device_, &cache, nullptr, &pipeline_cache_), "vkCreatePipelineCache");
  auto fence = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  vk_check(vkCreateFence(device_, &fence, nullptr, &fence_), "vkCreateFence");
}

std::string VulkanContext::describe() const {
  std::string s = std::string(properties_.deviceName) + " [" + device_type_name(properties_.deviceType);
  if (!driver_.empty()) s += ", " + driver_;
  return s + ", Vulkan " + version_string(properties_.apiVersion) + "]";
}

std::uint32_t VulkanContext::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                         VkMemoryPropertyFlags preferred) const {
  for (VkMemoryPropertyFlags want : {required | preferred, required}) {
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
      if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
    }
  }
  throw RunError("no Vulkan memory type with flags " + std::to_string(required) + " on " + describe());
}

void VulkanContext::submit_and_wait(VkCommandBuffer commands) {
  auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  vk_check(vkResetFences(device_, 1, &fence_), "vkResetFences");
  vk_check(vkQueueSubmit(queue_, 1, &submit, fence_), "vkQueueSubmit");
  vk_check(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

std::vector<std::string> VulkanContext::validation_messages() const {
  std::lock_guard lock(messages_mutex_);
  return messages_;
}

void VulkanContext::clear_validation_messages() {
  std::lock_guard lock(messages_mutex_);
  messages_.clear();
}

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* self) {
  auto* ctx = static_cast<VulkanContext*>(self);
  const char* level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
  std::lock_guard lock(ctx->messages_mutex_);
  ctx->messages_.push_back(std::string(level) + ": " + (data && data->pMessage ? data->pMessage : "(no message)"));
  return VK_FALSE;
}

bool vulkan_available(std::string* why) {
  static std::once_flag once;
  static std::string reason;
  static bool available = false;
  std::call_once(once, [] {
    try {
      VulkanContext probe;
      available = true;
    } catch (const std::exception& e) {
      reason = e.what();
    }
  });
  if (why) *why = reason;
  return available;
}

}  // namespace fracref
