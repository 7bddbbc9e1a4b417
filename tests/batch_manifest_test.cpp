// Batch manifests: strict reading (every error names the file and the key), sweep expansion
// into ids and overrides, defaults, and the scene rewriting that overrides need.
#include <gtest/gtest.h>

#include "batch/manifest.hpp"
#include "scene/json_strict.hpp"
#include "util/error.hpp"

using namespace fracref;
using nlohmann::json;

namespace {

const std::vector<std::string> kDemos = {"bunny", "branch", "wall", "clay", "jello"};

Manifest parse(const std::string& text) {
  return parse_manifest(parse_json_strict(text, "/data/m.json"), "/data/m.json", kDemos);
}

/// The message of the InputError that parsing `text` throws ("" when none is thrown).
std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(BatchManifest, ScenesAndDemosWithDefaultIdsAndPaths) {
  Manifest m = parse(R"({"jobs": [{"scene": "scenes/cube.json"}, {"scene": "/abs/b.json", "id": "other"},
                                   {"demo": "wall", "seed": 7, "stop_after": "refine", "backend": "cpu"}]})");
  EXPECT_EQ(m.file, "/data/m.json");
  ASSERT_EQ(m.jobs.size(), 3u);
  EXPECT_EQ(m.jobs[0].id, "cube");
  EXPECT_EQ(m.jobs[0].scene, "/data/scenes/cube.json");
  EXPECT_EQ(m.jobs[0].scene_as_written, "scenes/cube.json");
  EXPECT_TRUE(m.jobs[0].demo.empty());
  EXPECT_EQ(m.jobs[0].describe_overrides(), "");
  EXPECT_EQ(m.jobs[1].id, "other");
  EXPECT_EQ(m.jobs[1].scene, "/abs/b.json");
  EXPECT_EQ(m.jobs[2].id, "wall");
  EXPECT_EQ(m.jobs[2].demo, "wall");
  EXPECT_TRUE(m.jobs[2].scene.empty());
  EXPECT_EQ(m.jobs[2].seed, 7u);
  EXPECT_EQ(m.jobs[2].source, "jobs[2]");
  EXPECT_EQ(m.jobs[2].describe_overrides(), "seed=7 stop_after=refine backend=cpu");
}

TEST(BatchManifest, SweepExpandsTheProductInKeyOrderLastKeyFastest) {
  Manifest m = parse(R"({"jobs": [{"scene": "c.json", "weights.distance": 2,
                                   "sweep": {"seed": [1, 2, 3], "refine.tau": [0.001, 0.002]}}]})");
  ASSERT_EQ(m.jobs.size(), 6u);
  // Keys sorted: "refine.tau" before "seed"; seed varies fastest.
  const char* ids[] = {"c-refine.tau=0.001-seed=1", "c-refine.tau=0.001-seed=2", "c-refine.tau=0.001-seed=3",
                       "c-refine.tau=0.002-seed=1", "c-refine.tau=0.002-seed=2", "c-refine.tau=0.002-seed=3"};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(m.jobs[i].id, ids[i]);
    EXPECT_EQ(m.jobs[i].source, "jobs[0]");
    ASSERT_EQ(m.jobs[i].overrides.size(), 2u);
    EXPECT_EQ(m.jobs[i].overrides[0].first, "refine.tau");
    EXPECT_EQ(m.jobs[i].overrides[0].second, json(i < 3 ? 0.001 : 0.002));
    EXPECT_EQ(m.jobs[i].overrides[1].first, "weights.distance");
    EXPECT_EQ(m.jobs[i].seed, std::uint64_t(i % 3 + 1));
  }
  EXPECT_EQ(m.jobs[4].describe_overrides(), "seed=2 refine.tau=0.002 weights.distance=2");
}

TEST(BatchManifest, SweepOverArraysBackendsAndStages) {
  Manifest m = parse(R"([{"demo": "clay", "id": "c", "sweep": {"field.resolution": [[16, 16, 16], [32, 32, 8]],
                                                              "backend": ["cpu", "vulkan"]}}])");
  ASSERT_EQ(m.jobs.size(), 4u);
  EXPECT_EQ(m.jobs[0].id, "c-backend=cpu-field.resolution=16x16x16");
  EXPECT_EQ(m.jobs[3].id, "c-backend=vulkan-field.resolution=32x32x8");
  EXPECT_EQ(m.jobs[3].backend, "vulkan");
  EXPECT_EQ(m.jobs[3].overrides.at(0).second, json::parse("[32, 32, 8]"));
}

TEST(BatchManifest, DefaultsApplyUnlessTheJobOrItsSweepSaysOtherwise) {
  Manifest m = parse(R"({"defaults": {"seed": 5, "backend": "cpu", "refine.max_iterations": 3},
                         "jobs": [{"scene": "a.json"}, {"scene": "b.json", "backend": "auto", "refine.max_iterations": 9},
                                  {"scene": "c.json", "sweep": {"seed": [8]}}]})");
  ASSERT_EQ(m.jobs.size(), 3u);
  EXPECT_EQ(m.jobs[0].seed, 5u);
  EXPECT_EQ(m.jobs[0].backend, "cpu");
  EXPECT_EQ(m.jobs[0].overrides.at(0).second, json(3));
  EXPECT_EQ(m.jobs[1].backend, "auto");
  EXPECT_EQ(m.jobs[1].overrides.at(0).second, json(9));
  EXPECT_EQ(m.jobs[2].seed, 8u);
  EXPECT_EQ(m.jobs[2].id, "c-seed=8");
}

TEST(BatchManifest, ErrorsNameTheFileAndTheKey) {
  struct Case {
    std::string text, expect;
  } cases[] = {
      {R"({"jobs": [{"scene": "a.json", "seeed": 3}]})", "key 'jobs[0].seeed': unknown key (did you mean 'seed'?)"},
      {R"({"jobz": []})", "key 'jobz': unknown key (did you mean 'jobs'?)"},
      {R"({"comment": "x"})", "key 'jobs': required key is missing"},
      {R"({"jobs": []})", "key 'jobs': must be a non-empty array"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"seed": 3}}]})", "key 'jobs[0].sweep.seed': must be a non-empty array"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"seed": []}}]})", "key 'jobs[0].sweep.seed': must be a non-empty array"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"seed": [1, -2]}}]})", "key 'jobs[0].sweep.seed[1]': must be an integer >= 0, got -2"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"seed": [1, "2"]}}]})", "key 'jobs[0].sweep.seed[1]': expected an integer"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"colour": [1]}}]})", "key 'jobs[0].sweep.colour': cannot be swept"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"backend": ["gpu"]}}]})", "key 'jobs[0].sweep.backend[0]'"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"refine.tau": [{}]}}]})", "key 'jobs[0].sweep.refine.tau[0]'"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {}}]})", "key 'jobs[0].sweep': must name at least one key"},
      {R"({"jobs": [{"scene": "a.json", "seed": 1, "sweep": {"seed": [2]}}]})", "key 'jobs[0].sweep.seed': is also set"},
      {R"({"jobs": [{"scene": "a.json", "refine..tau": 1}]})", "key 'jobs[0].refine..tau': a scene override must be dotted"},
      {R"({"jobs": [{"scene": "a.json", "refine.tau": null}]})", "key 'jobs[0].refine.tau': a scene override cannot be null"},
      {R"({"jobs": [{"scene": "a.json", "demo": "wall"}]})", "key 'jobs[0]': give exactly one of 'scene'"},
      {R"({"jobs": [{"seed": 1}]})", "key 'jobs[0]': give exactly one of 'scene'"},
      {R"({"jobs": [{"demo": "volcano"}]})", "key 'jobs[0].demo'"},
      {R"({"jobs": [{"scene": 3}]})", "key 'jobs[0].scene': expected a string"},
      {R"({"jobs": [{"scene": "a.json", "stop_after": "later"}]})", "key 'jobs[0].stop_after'"},
      {R"({"jobs": [{"scene": "a.json", "id": "../up"}]})", "key 'jobs[0].id': '../up' is not a usable folder name"},
      {R"({"jobs": [{"scene": "x/a.json"}, {"scene": "y/a.json"}]})",
       "key 'jobs[1]': job id 'a' is already used by jobs[0]"},
      {R"({"jobs": [{"scene": "a.json", "sweep": {"seed": [1, 1]}}]})", "job id 'a-seed=1' is already used"},
      {R"({"defaults": {"scene": "a.json"}, "jobs": [{"scene": "a.json"}]})", "key 'defaults.scene': unknown key"},
      {R"({"jobs": [3]})", "key 'jobs[0]'"},
      {R"({"jobs": [{"scene": "a.json", "seed": 1, "seed": 2}]})", "duplicate key"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find("/data/m.json"), std::string::npos) << c.text << " -> " << e;
    EXPECT_NE(e.find(c.expect), std::string::npos) << c.text << " -> " << e;
  }
}

TEST(BatchManifest, LoadNamesAMissingFile) {
  try {
    load_manifest("/nonexistent/manifest.json", kDemos);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/manifest.json"), std::string::npos) << e.what();
  }
}

TEST(BatchManifest, OverridesSetNestedKeysAndRefuseNonObjects) {
  json scene = json::parse(R"({"exterior": "a.obj", "refine": {"tau": 1}})");
  apply_overrides(scene, {{"refine.tau", 0.5}, {"weights.distance", 2}, {"field.params.scale", 3}}, "s.json");
  EXPECT_EQ(scene["refine"]["tau"], json(0.5));
  EXPECT_EQ(scene["weights"]["distance"], json(2));
  EXPECT_EQ(scene["field"]["params"]["scale"], json(3));
  try {
    apply_overrides(scene, {{"exterior.file", 1}}, "s.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: override 'exterior.file': 'exterior' is not an object"),
              std::string::npos)
        << e.what();
  }
}

TEST(BatchManifest, AnchorMakesEveryScenePathAbsolute) {
  json scene = json::parse(R"({"exterior": "m/a.obj",
    "fracture": {"kind": "pieces", "files": ["p0.obj", "/abs/p1.obj"], "cracks": "c.txt"},
    "animation": {"kind": "frames", "frames": "f/frame_{:04}.txt", "parent_map": "f/p.txt", "count": 2},
    "field": {"type": "grid", "file": "g.raw"}})");
  anchor_scene_paths(scene, "/s", "orig");
  EXPECT_EQ(scene["exterior"], "/s/m/a.obj");
  EXPECT_EQ(scene["fracture"]["files"][0], "/s/p0.obj");
  EXPECT_EQ(scene["fracture"]["files"][1], "/abs/p1.obj");
  EXPECT_EQ(scene["fracture"]["cracks"], "/s/c.txt");
  EXPECT_EQ(scene["animation"]["frames"], "/s/f/frame_{:04}.txt");
  EXPECT_EQ(scene["animation"]["parent_map"], "/s/f/p.txt");
  EXPECT_EQ(scene["field"]["file"], "/s/g.raw");
  EXPECT_EQ(scene["name"], "orig");
  json named = json::parse(R"({"name": "mine", "exterior": "a.obj"})");
  anchor_scene_paths(named, "/s", "orig");
  EXPECT_EQ(named["name"], "mine");
}
