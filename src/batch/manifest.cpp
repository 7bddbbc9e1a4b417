#include "batch/manifest.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include "scene/json_strict.hpp"
#include "util/error.hpp"

namespace fracref {
namespace fs = std::filesystem;
namespace {

using nlohmann::json;

const std::vector<std::string> kStages = {"preprocess", "refine", "pieces", "animate"};
const std::vector<std::string> kBackends = {"cpu", "vulkan", "auto"};
constexpr std::size_t kMaxJobs = 100000;

/// "refine.tau", "weights.distance", "field.params.scale": two or more identifiers.
bool is_scene_key(const std::string& key) {
  if (key.find('.') == std::string::npos) return false;
  std::size_t start = 0;
  while (start <= key.size()) {
    std::size_t end = key.find('.', start);
    if (end == std::string::npos) end = key.size();
    if (end == start) return false;
    for (std::size_t i = start; i < end; ++i) {
      const char c = key[i];
      const bool ok = std::isalpha((unsigned char)c) || c == '_' || (i > start && std::isdigit((unsigned char)c));
      if (!ok) return false;
    }
    start = end + 1;
  }
  return true;
}

bool is_valid_id(const std::string& id) {
  if (id.empty() || id.size() > 200 || id[0] == '.' || id[0] == '-') return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum((unsigned char)c) || c == '.' || c == '_' || c == '-' || c == '=' || c == '+';
  });
}

/// A value as it reads in a job id: "0.001", "cpu", "true", "16x16x16"; unsafe characters as '_'.
std::string id_text(const json& v) {
  std::string s;
  if (v.is_string()) s = v.get<std::string>();
  else if (v.is_array())
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i) s += 'x';
      s += id_text(v[i]);
    }
  else s = v.dump();
  for (char& c : s)
    if (!(std::isalnum((unsigned char)c) || c == '.' || c == '_' || c == '-' || c == '+')) c = '_';
  return s;
}

/// The settings a job and the manifest's "defaults" share.
struct Settings {
  std::optional<std::uint64_t> seed;
  std::string stop_after, backend;
  std::map<std::string, json> overrides;
};

/// Reads seed, stop_after, backend and the dotted scene keys of `r`.
Settings read_settings(ObjectReader& r, const json& value) {
  Settings s;
  if (r.has("seed")) s.seed = std::uint64_t(r.integer("seed", 0, IntRange::at_least(0)));
  s.stop_after = r.choice("stop_after", kStages, "");
  s.backend = r.choice("backend", kBackends, "");
  for (const auto& [key, v] : value.items()) {
    if (key.find('.') == std::string::npos) continue;  // finish() reports unknown plain keys
    if (!is_scene_key(key)) throw r.error(key, "a scene override must be dotted identifiers such as 'refine.tau'");
    if (v.is_null()) throw r.error(key, "a scene override cannot be null");
    r.has(key);
    s.overrides[key] = v;
  }
  return s;
}

/// Checks one sweep value through an ObjectReader so that the message names "<key>[i]".
void check_sweep_value(const std::string& key, const json& v, std::size_t i, const ObjectReader& sweep) {
  const std::string name = key + "[" + std::to_string(i) + "]";
  json wrapper = json::object();
  wrapper[name] = v;
  ObjectReader r(wrapper, sweep.file(), sweep.object_path());
  if (key == "seed") r.integer(name, 0, IntRange::at_least(0));
  else if (key == "stop_after") r.choice(name, kStages, "");
  else if (key == "backend") r.choice(name, kBackends, "");
  else if (v.is_null() || v.is_object()) throw r.error(name, "a swept scene value must be a number, string, boolean or array");
}

/// The sweep's axes in key order (sorted): key and its values.
std::vector<std::pair<std::string, std::vector<json>>> read_sweep(ObjectReader& job, const Settings& own) {
  std::vector<std::pair<std::string, std::vector<json>>> axes;
  std::optional<ObjectReader> sweep = job.object("sweep");
  if (!sweep) return axes;
  const json& value = job.raw_object("sweep");
  if (value.empty()) throw job.error("sweep", "must name at least one key to sweep");
  for (const auto& [key, values] : value.items()) {
    const bool plain = key == "seed" || key == "stop_after" || key == "backend";
    if (!plain && !is_scene_key(key))
      throw sweep->error(key, "cannot be swept (sweep seed, stop_after, backend or a dotted scene key such as 'refine.tau')");
    if (!values.is_array() || values.empty())
      throw sweep->error(key, "must be a non-empty array of the values to run");
    const bool set = (key == "seed" && own.seed) || (key == "stop_after" && !own.stop_after.empty()) ||
                     (key == "backend" && !own.backend.empty()) || own.overrides.count(key);
    if (set) throw sweep->error(key, "is also set in the job; give it in one place");
    for (std::size_t i = 0; i < values.size(); ++i) check_sweep_value(key, values[i], i, *sweep);
    sweep->has(key);
    axes.push_back({key, std::vector<json>(values.begin(), values.end())});
  }
  sweep->finish();
  return axes;
}

void set_value(Settings& s, const std::string& key, const json& v) {
  if (key == "seed") s.seed = v.get<std::uint64_t>();
  else if (key == "stop_after") s.stop_after = v.get<std::string>();
  else if (key == "backend") s.backend = v.get<std::string>();
  else s.overrides[key] = v;
}

BatchJob make_job(const std::string& id, const std::string& source, const BatchJob& base, const Settings& s) {
  BatchJob j = base;
  j.id = id;
  j.source = source;
  j.seed = s.seed;
  j.stop_after = s.stop_after;
  j.backend = s.backend;
  j.overrides.assign(s.overrides.begin(), s.overrides.end());
  return j;
}

/// Appends the jobs of manifest entry `index` (one, or one per point of its sweep).
void read_job(const json& value, std::size_t index, const fs::path& file, const Settings& defaults,
              const std::vector<std::string>& demo_names, std::vector<BatchJob>& out) {
  const std::string source = "jobs[" + std::to_string(index) + "]";
  ObjectReader r(value, file.string(), source);
  r.string("comment", "");
  BatchJob base;
  const bool has_scene = r.has("scene"), has_demo = r.has("demo");
  if (has_scene == has_demo) throw r.object_error("give exactly one of 'scene' (a scene file) and 'demo' (a demo name)");
  if (has_scene) {
    base.scene_as_written = r.string_required("scene");
    base.scene = r.path_required("scene", file.parent_path());
  } else {
    base.demo = base.scene_as_written = r.choice_required("demo", demo_names);
  }
  std::string id = r.string("id", has_scene ? base.scene.stem().string() : base.demo);
  if (!is_valid_id(id))
    throw r.error("id", "'" + id + "' is not a usable folder name (letters, digits and . _ - = +; not starting with . or -)");
  const Settings own = read_settings(r, value);
  const auto axes = read_sweep(r, own);
  r.finish();
  Settings merged = defaults;
  if (own.seed) merged.seed = own.seed;
  if (!own.stop_after.empty()) merged.stop_after = own.stop_after;
  if (!own.backend.empty()) merged.backend = own.backend;
  for (const auto& [k, v] : own.overrides) merged.overrides[k] = v;
  std::size_t total = 1;
  for (const auto& axis : axes) {
    total *= axis.second.size();
    if (total > kMaxJobs) throw r.error("sweep", "expands to more than " + std::to_string(kMaxJobs) + " jobs");
  }
  // Odometer over the axes, the last key varying fastest.
  std::vector<std::size_t> at(axes.size(), 0);
  for (std::size_t n = 0; n < total; ++n) {
    Settings s = merged;
    std::string job_id = id;
    for (std::size_t a = 0; a < axes.size(); ++a) {
      set_value(s, axes[a].first, axes[a].second[at[a]]);
      job_id += "-" + axes[a].first + "=" + id_text(axes[a].second[at[a]]);
    }
    out.push_back(make_job(job_id, source, base, s));
    for (std::size_t a = axes.size(); a-- > 0;) {
      if (++at[a] < axes[a].second.size()) break;
      at[a] = 0;
    }
  }
}

}  // namespace

std::string BatchJob::describe_overrides() const {
  std::string s;
  auto add = [&](const std::string& k, const std::string& v) {
    if (!s.empty()) s += ' ';
    s += k + "=" + v;
  };
  if (seed) add("seed", std::to_string(*seed));
  if (!stop_after.empty()) add("stop_after", stop_after);
  if (!backend.empty()) add("backend", backend);
  for (const auto& [k, v] : overrides) add(k, v.is_string() ? v.get<std::string>() : v.dump());
  return s;
}

Manifest parse_manifest(const json& value, const fs::path& file, const std::vector<std::string>& demo_names) {
  Manifest m;
  m.file = (file.empty() ? fs::current_path() : fs::absolute(file)).lexically_normal();
  const json wrapped = value.is_array() ? json{{"jobs", value}} : value;
  ObjectReader root(wrapped, file.string(), "");
  root.string("$schema", "");
  root.string("comment", "");
  Settings defaults;
  if (root.has("defaults")) {
    ObjectReader d = root.object_required("defaults");
    defaults = read_settings(d, wrapped["defaults"]);
    d.finish();
  }
  if (!root.has("jobs")) {
    root.finish();  // a misspelt "jobs" is reported as such
    throw root.error("jobs", "required key is missing");
  }
  const json& jobs = wrapped["jobs"];
  if (!jobs.is_array() || jobs.empty()) throw root.error("jobs", "must be a non-empty array of job objects");
  root.finish();
  for (std::size_t i = 0; i < jobs.size(); ++i) read_job(jobs[i], i, m.file, defaults, demo_names, m.jobs);
  std::map<std::string, std::string> seen;
  for (const BatchJob& j : m.jobs) {
    auto [it, fresh] = seen.emplace(j.id, j.source);
    if (!fresh)
      throw InputError(file.string() + ": key '" + j.source + "': job id '" + j.id + "' is already used by " +
                       it->second + "; give one of them an \"id\"");
  }
  if (m.jobs.size() > kMaxJobs) throw root.error("jobs", "expand to more than " + std::to_string(kMaxJobs) + " jobs");
  return m;
}

Manifest load_manifest(const fs::path& file, const std::vector<std::string>& demo_names) {
  return parse_manifest(read_json_file(file), file, demo_names);
}

void apply_overrides(json& scene, const std::vector<SceneOverride>& overrides, const std::string& label) {
  for (const auto& [key, value] : overrides) {
    json* at = &scene;
    std::size_t start = 0;
    for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
      const std::string part = key.substr(start, dot - start);
      if (!at->is_object()) break;
      json& next = (*at)[part];
      if (next.is_null()) next = json::object();
      if (!next.is_object())
        throw InputError(label + ": override '" + key + "': '" + key.substr(0, dot) + "' is not an object in the scene");
      at = &next;
      start = dot + 1;
    }
    (*at)[key.substr(start)] = value;
  }
}

void anchor_scene_paths(json& scene, const fs::path& scene_dir, const std::string& default_name) {
  if (!scene.is_object()) return;
  auto anchor = [&](json& v) {
    if (v.is_string() && !v.get<std::string>().empty() && fs::path(v.get<std::string>()).is_relative())
      v = (scene_dir / v.get<std::string>()).lexically_normal().string();
  };
  auto member = [](json& o, const char* key) -> json* {
    return o.is_object() && o.contains(key) ? &o[key] : nullptr;
  };
  if (json* e = member(scene, "exterior")) anchor(*e);
  if (json* f = member(scene, "fracture")) {
    for (const char* k : {"mesh", "cracks"})
      if (json* v = member(*f, k)) anchor(*v);
    if (json* files = member(*f, "files"); files && files->is_array())
      for (json& v : *files) anchor(v);
  }
  if (json* a = member(scene, "animation"))
    for (const char* k : {"frames", "parent_map", "transforms"})
      if (json* v = member(*a, k)) anchor(*v);
  if (json* fl = member(scene, "field"))
    if (json* v = member(*fl, "file")) anchor(*v);
  if (!scene.contains("name")) scene["name"] = default_name;
}

}  // namespace fracref
