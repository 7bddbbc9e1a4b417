#pragma once
// One refinement job, scene file to output folder: load → preprocess → field → refine → pieces
// → animate, with report.json and a preview picture. The CLI's `refine`, `demo` and `batch` and
// the bench all run jobs through run_job().
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "flow/backend.hpp"
#include "scene/scene.hpp"

namespace fracref {

/// The last stage a job runs (--stop-after).
enum class Stage { preprocess = 0, refine = 1, pieces = 2, animate = 3 };

/// "preprocess", "refine", "pieces", "animate". \throw InputError on anything else.
Stage parse_stage(const std::string& name);
const char* to_string(Stage stage);

/// Progress callback: stage name, fraction of the stage done in [0, 1], a short detail line.
using JobProgress = std::function<void(const std::string& stage, double fraction, const std::string& detail)>;

struct JobOptions {
  Stage stop_after = Stage::animate;
  std::optional<std::uint64_t> seed;      ///< overrides scene.refine.seed
  std::optional<int> preview_frames;      ///< overrides scene.output.preview_frames
  JobProgress progress;                   ///< may be empty
};

/// Runs the job, writing every output file into `out` (an existing, empty staging folder: the
/// caller renames it into place when this returns), and returns report.json's content (also
/// written to out/report.json).
/// \throw InputError on bad input (naming the file, line or key), RunError on failures.
nlohmann::ordered_json run_job(const Scene& scene, const std::filesystem::path& out, ComputeBackend& backend,
                               const JobOptions& options);

}  // namespace fracref
