#include "cli_backend.hpp"

#include "util/error.hpp"
#include "vk_backend.hpp"

namespace fracref::cli {
namespace {

std::unique_ptr<ComputeBackend> choose_automatically(std::string& note) {
  try {
    std::unique_ptr<ComputeBackend> vk = make_vulkan_backend();
    auto* backend = dynamic_cast<VulkanBackend*>(vk.get());
    VkPhysicalDeviceType type = backend->context().properties().deviceType;
    if (type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU || type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU) return vk;
    note = "backend auto -> cpu (" + backend->name() + " is a CPU device: the CPU backend does the same work without Vulkan)";
  } catch (const RunError& e) {
    note = std::string("backend auto -> cpu (") + e.what() + ")";
  }
  return make_cpu_backend();
}

}  // namespace

std::unique_ptr<ComputeBackend> make_backend(const std::string& name, std::string& note) {
  note.clear();
  if (name == "cpu") return make_cpu_backend();
  if (name == "vulkan") return make_vulkan_backend();
  if (name == "auto") return choose_automatically(note);
  throw InputError("--backend: unknown backend '" + name + "' (cpu, vulkan, auto)");
}

}  // namespace fracref::cli
