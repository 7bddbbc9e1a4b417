#include "cli_backend.hpp"

#include <iostream>

#include "util/error.hpp"

namespace fracref::cli {

std::unique_ptr<ComputeBackend> make_backend(const std::string& name, bool quiet) {
  if (name == "cpu") return make_cpu_backend(2);
  if (name == "vulkan") throw RunError("--backend vulkan: the Vulkan backend is not implemented yet in this version");
  if (name == "auto") {
    if (!quiet) std::cerr << "fracref: backend auto -> cpu (the Vulkan flow kernels are not in this version yet)\n";
    return make_cpu_backend(2);
  }
  throw InputError("--backend: unknown backend '" + name + "' (cpu, vulkan, auto)");
}

}  // namespace fracref::cli
