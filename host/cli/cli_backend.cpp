#include "cli_backend.hpp"

#include <iostream>

#include "util/error.hpp"
#include "vk_backend.hpp"

namespace fracref::cli {
namespace {

std::unique_ptr<ComputeBackend> choose_automatically(bool quiet) {
  try {
    std::unique_ptr<ComputeBackend> vk = make_vulkan_backend();
    auto* backend = dynamic_cast<VulkanBackend*>(vk.get());
    VkPhysicalDeviceType type = backend->context().properties().deviceType;
    if (type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU || type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU) return vk;
    if (!quiet)
      std::cerr << "fracref: backend auto -> cpu (" << backend->name()
                << " is a CPU device: the CPU backend does the same work without Vulkan)\n";
  } catch (const RunError& e) {
    if (!quiet) std::cerr << "fracref: backend auto -> cpu (" << e.what() << ")\n";
  }
  return make_cpu_backend();
}

}  // namespace

std::unique_ptr<ComputeBackend> make_backend(const std::string& name, bool quiet) {
  if (name == "cpu") return make_cpu_backend();
  if (name == "vulkan") return make_vulkan_backend();
  if (name == "auto") return choose_automatically(quiet);
  throw InputError("--backend: unknown backend '" + name + "' (cpu, vulkan, auto)");
}

}  // namespace fracref::cli
