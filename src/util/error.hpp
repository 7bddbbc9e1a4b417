#pragma once
// Error types shared by every room of fracref, and the exit codes the CLI maps them to.
#include <stdexcept>
#include <string>

namespace fracref {

/// Exit codes of the `fracref` CLI (documented in the README).
enum ExitCode : int {
  kExitOk = 0,       ///< success
  kExitFailure = 1,  ///< a failure while running (Vulkan device lost, I/O error on output, ...)
  kExitBadInput = 2, ///< bad input or usage: the message names the file, line or key
};

/// Bad user input: a malformed file, a bad scene key, a wrong command line.
/// The message is complete and user-facing, e.g. "mesh.obj:12: coordinate is NaN".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A failure while running that is not the user's input (device lost, disk full, ...).
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "file:line: what" — the one format for located input errors.
inline InputError input_error_at(const std::string& file, std::size_t line, const std::string& what) {
  return InputError(file + ":" + std::to_string(line) + ": " + what);
}

}  // namespace fracref
