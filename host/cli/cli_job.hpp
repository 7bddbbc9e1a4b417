#pragma once
// Options shared by `refine` and `demo`, and the functions that run them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fracref::cli {

struct JobCliOptions {
  std::string scene;          ///< scene file (refine) or built-in name (demo)
  std::string output;
  std::string backend = "auto";
  std::optional<std::uint64_t> seed;
  std::string stop_after = "animate";
  int preview_frames = 0;
  bool quiet = false;
  bool list = false;          ///< demo --list
  std::vector<std::string> sets;  ///< --set KEY=VALUE, scene keys by dotted path
};

/// \throw InputError on a bad scene, RunError on failures while running.
int run_refine(const JobCliOptions& options);
/// \throw InputError on an unknown scene name.
int run_demo(const JobCliOptions& options);

}  // namespace fracref::cli
