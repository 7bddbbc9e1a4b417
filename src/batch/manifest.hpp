#pragma once
// A batch manifest (scenes/BATCH.md): a list of refinement jobs, each a scene file or a demo
// name with optional overrides and sweeps, read strictly and expanded into one BatchJob per run.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace fracref {

/// A dotted scene key ("refine.tau") and the JSON value it is set to.
using SceneOverride = std::pair<std::string, nlohmann::json>;

/// One job after sweep expansion.
struct BatchJob {
  std::string id;                        ///< unique in the manifest; the job's folder name
  std::string source;                    ///< where it came from, for messages: "jobs[2]"
  std::filesystem::path scene;           ///< absolute scene file, or empty for a demo job
  std::string scene_as_written;          ///< the manifest's string (scene path or demo name)
  std::string demo;                      ///< demo name, or empty for a scene job
  std::optional<std::uint64_t> seed;     ///< --seed of the job command
  std::string stop_after;                ///< "" = the runner's default
  std::string backend;                   ///< "" = the runner's default
  std::vector<SceneOverride> overrides;  ///< sorted by key; applied to the scene's JSON

  /// "seed=3 stop_after=refine refine.tau=0.001" (empty when the job has none): every setting
  /// the job gives beyond its scene, for summaries.
  std::string describe_overrides() const;
};

struct Manifest {
  std::filesystem::path file;  ///< absolute and lexically normal
  std::vector<BatchJob> jobs;  ///< in manifest order; sweeps expanded in place
};

/// Reads and expands a manifest file. Relative scene paths are resolved against its folder.
/// \throw InputError naming the file and the key by its dotted path ("jobs[1].sweep.seed")
///        for bad JSON, an unknown or missing key, a wrong type or range, a bad sweep (not a
///        non-empty array of scalars, a key both set and swept), an unknown demo name, both or
///        neither of scene/demo, a bad id, or two jobs with the same id.
/// `demo_names` are the names a "demo" job may give (demo_scene_names(); passed in so that this
/// room does not depend on the scene generator).
Manifest load_manifest(const std::filesystem::path& file, const std::vector<std::string>& demo_names);

/// As load_manifest for already parsed JSON (an object with "jobs", or a bare array of jobs);
/// `file` names it in messages and anchors relative paths.
Manifest parse_manifest(const nlohmann::json& json, const std::filesystem::path& file,
                        const std::vector<std::string>& demo_names);

/// Sets every override in `scene` (a parsed scene file): "refine.tau" sets scene["refine"]["tau"],
/// creating missing objects on the way.
/// \throw InputError "<label>: override 'a.b': 'a' is not an object in the scene" when a
///        prefix of the key names a non-object value.
void apply_overrides(nlohmann::json& scene, const std::vector<SceneOverride>& overrides, const std::string& label);

/// Makes every relative path of a scene file (exterior, fracture.mesh/files/cracks,
/// animation.frames/parent_map/transforms, field.file) absolute against `scene_dir`, and sets
/// "name" to `default_name` when absent, so that the scene can be written to another folder
/// and still mean the same job.
void anchor_scene_paths(nlohmann::json& scene, const std::filesystem::path& scene_dir, const std::string& default_name);

}  // namespace fracref
