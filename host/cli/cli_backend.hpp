#pragma once
// Choosing the compute backend for --backend cpu|vulkan|auto.
#include <memory>
#include <string>

#include "flow/backend.hpp"

namespace fracref::cli {

/// cpu: the CPU backend (never touches Vulkan). vulkan: the Vulkan backend, or a RunError saying
/// why it cannot run. auto: Vulkan on a discrete or integrated GPU; the CPU backend on a CPU
/// Vulkan device such as lavapipe (a CPU device: the CPU backend does the same work without Vulkan) or
/// when Vulkan is unavailable, saying why in `note` (one line, "backend auto -> cpu (...)"; empty
/// otherwise): the caller prints it once the run has succeeded, so that a failing run says one
/// thing, its error.
/// \throw InputError for an unknown name, RunError when vulkan was asked for and cannot run.
std::unique_ptr<ComputeBackend> make_backend(const std::string& name, std::string& note);

}  // namespace fracref::cli
