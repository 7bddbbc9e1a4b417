// The scene schema: exact values, defaults, resolved paths, and one test per class of error,
// each asserting that the message names the file and the key's dotted path.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "scene/json_strict.hpp"
#include "scene/scene.hpp"
#include "util/input_size.hpp"

namespace fracref {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

const fs::path kFile = "/jobs/bunny/scene.json";

/// A minimal valid scene; tests patch it with JSON merge-patch semantics.
json minimal() {
  return json::parse(R"({
    "exterior": "bunny.obj",
    "fracture": {"kind": "tets", "mesh": "coarse.mesh"},
    "field": {"type": "marble", "resolution": [50, 50, 50]}
  })");
}

Scene parse_patched(const std::string& patch) {
  json j = minimal();
  j.merge_patch(json::parse(patch));
  return parse_scene(j, kFile);
}

std::string patched_error(const std::string& patch) {
  return input_error([&] { parse_patched(patch); });
}

const char* kComplete = R"({
  "$schema": "https://example.org/fracref-scene.json",
  "comment": "every key set",
  "name": "marble bunny",
  "exterior": "../models/bunny.obj",
  "fracture": {"kind": "pieces", "files": ["pieces/a.obj", "/abs/b.obj"], "virtual_fracture": false},
  "animation": {"kind": "frames", "frames": "frames/frame_{:04}.txt", "first": 3, "count": 48,
                "parent_map": "frames/parents.txt", "fps": 30},
  "field": {"type": "wood", "resolution": [32, 64, 16], "padding": 0.1, "seed": 7,
            "params": {"rings": 12, "color": [1, 0, 0]}},
  "weights": {"strength": 2.0, "distance": 0, "offset": 0.25},
  "pyramid": {"levels": 6, "sigma": 1.5},
  "refine": {"tau": 0.003, "delta": 0.005, "step": 0.01, "tolerance": 1e-6, "max_iterations": 0,
             "max_triangles": 1000, "seed": 42, "min_angle": 0, "collisions": false,
             "rim_motion": true, "tangential_motion": false, "relax": 0.25, "rim_smoothing": 3,
             "fold_solves": 3},
  "output": {"ply": false, "obj": true, "glb": false, "frames": false, "frames_format": "obj", "preview": false, "preview_frames": 12}
})";

TEST(ParseScene, CompleteSceneHasExactValues) {
  const Scene s = parse_scene(json::parse(kComplete), kFile);
  EXPECT_EQ(s.file, fs::path("/jobs/bunny/scene.json"));
  EXPECT_EQ(s.name, "marble bunny");
  EXPECT_EQ(s.exterior, fs::path("/jobs/models/bunny.obj"));
  EXPECT_EQ(s.fracture.kind, FractureKind::pieces);
  EXPECT_TRUE(s.fracture.mesh.empty());
  EXPECT_EQ(s.fracture.files, (std::vector<fs::path>{"/jobs/bunny/pieces/a.obj", "/abs/b.obj"}));
  EXPECT_TRUE(s.fracture.cracks.empty());
  EXPECT_FALSE(s.fracture.virtual_fracture);
  EXPECT_EQ(s.animation.kind, AnimationKind::frames);
  EXPECT_EQ(s.animation.frames, fs::path("/jobs/bunny/frames/frame_{:04}.txt"));
  EXPECT_EQ(s.animation.first, 3);
  EXPECT_EQ(s.animation.count, 48);
  EXPECT_EQ(s.animation.parent_map, fs::path("/jobs/bunny/frames/parents.txt"));
  EXPECT_TRUE(s.animation.transforms.empty());
  EXPECT_EQ(s.animation.fps, 30.0);
  EXPECT_EQ(s.field.type, FieldType::wood);
  EXPECT_EQ(s.field.resolution, glm::uvec3(32, 64, 16));
  EXPECT_EQ(s.field.padding, 0.1);
  EXPECT_EQ(s.field.seed, 7u);
  EXPECT_TRUE(s.field.file.empty());
  EXPECT_EQ(s.field.params, json::parse(R"({"rings": 12, "color": [1, 0, 0]})"));
  EXPECT_EQ(s.weights.strength, 2.0);
  EXPECT_EQ(s.weights.distance, 0.0);
  EXPECT_EQ(s.weights.offset, 0.25);
  EXPECT_EQ(s.pyramid.levels, 6);
  EXPECT_EQ(s.pyramid.sigma, 1.5);
  EXPECT_EQ(s.refine.tau, 0.003);
  EXPECT_EQ(s.refine.delta, 0.005);
  EXPECT_EQ(s.refine.step, 0.01);
  EXPECT_EQ(s.refine.tolerance, 1e-6);
  EXPECT_EQ(s.refine.max_iterations, 0);
  EXPECT_EQ(s.refine.max_triangles, 1000);
  EXPECT_EQ(s.refine.seed, 42u);
  EXPECT_EQ(s.refine.min_angle, 0.0);
  EXPECT_FALSE(s.refine.collisions);
  EXPECT_TRUE(s.refine.rim_motion);
  EXPECT_FALSE(s.refine.tangential_motion);
  EXPECT_EQ(s.refine.relax, 0.25);
  EXPECT_EQ(s.refine.rim_smoothing, 3);
  EXPECT_EQ(s.refine.fold_solves, 3);
  EXPECT_FALSE(s.output.ply);
  EXPECT_TRUE(s.output.obj);
  EXPECT_FALSE(s.output.glb);
  EXPECT_FALSE(s.output.frames);
  EXPECT_EQ(s.output.frames_format, "obj");
  EXPECT_FALSE(s.output.preview);
  EXPECT_EQ(s.output.preview_frames, 12);
}

TEST(ParseScene, DefaultsAreTheDocumentedOnes) {
  const Scene s = parse_scene(minimal(), kFile);
  EXPECT_EQ(s.name, "scene");  // the file's stem
  EXPECT_EQ(s.exterior, fs::path("/jobs/bunny/bunny.obj"));
  EXPECT_EQ(s.fracture.kind, FractureKind::tets);
  EXPECT_EQ(s.fracture.mesh, fs::path("/jobs/bunny/coarse.mesh"));
  EXPECT_TRUE(s.fracture.files.empty());
  EXPECT_TRUE(s.fracture.cracks.empty());
  EXPECT_TRUE(s.fracture.virtual_fracture);
  EXPECT_EQ(s.animation.kind, AnimationKind::none);
  EXPECT_EQ(s.animation.fps, 24.0);
  EXPECT_EQ(s.field.padding, 0.05);
  EXPECT_EQ(s.field.seed, 1u);
  EXPECT_EQ(s.field.params, json::object());
  EXPECT_EQ(s.weights.strength, 1.0);
  EXPECT_EQ(s.weights.distance, 4.0);
  EXPECT_EQ(s.weights.offset, 0.05);
  EXPECT_EQ(s.pyramid.levels, 5);
  EXPECT_EQ(s.pyramid.sigma, 1.0);
  EXPECT_EQ(s.refine.tau, 0.002);
  EXPECT_EQ(s.refine.delta, 0.004);
  EXPECT_EQ(s.refine.step, 0.0);
  EXPECT_EQ(s.refine.tolerance, 5e-4);
  EXPECT_EQ(s.refine.max_iterations, 200);
  EXPECT_EQ(s.refine.max_triangles, 2000000);
  EXPECT_EQ(s.refine.seed, 1u);
  EXPECT_EQ(s.refine.min_angle, 20.0);
  EXPECT_TRUE(s.refine.collisions);
  EXPECT_FALSE(s.refine.rim_motion);
  EXPECT_TRUE(s.refine.tangential_motion);
  EXPECT_EQ(s.refine.relax, 0.0);
  EXPECT_FALSE(s.refine.rim_smoothing.has_value());  // the input's default (job.cpp)
  EXPECT_EQ(s.refine.fold_solves, 2);
  EXPECT_TRUE(s.output.ply && s.output.obj && s.output.glb && s.output.preview);
  EXPECT_FALSE(s.output.frames);  // frames/ only on request
  EXPECT_EQ(s.output.frames_format, "bin");
  EXPECT_EQ(s.output.preview_frames, 0);
  // Empty sub-objects give the same defaults.
  const Scene e = parse_patched(R"({"weights": {}, "pyramid": {}, "refine": {}, "output": {}})");
  EXPECT_EQ(e.refine.tau, 0.002);
  EXPECT_EQ(e.pyramid.levels, 5);
}

TEST(ParseScene, OtherVariants) {
  const Scene t = parse_patched(R"({"fracture": {"cracks": "c/cracks.txt"},
                                    "animation": {"kind": "rigid", "transforms": "rigid.txt"}})");
  EXPECT_EQ(t.fracture.cracks, fs::path("/jobs/bunny/c/cracks.txt"));
  EXPECT_EQ(t.animation.kind, AnimationKind::rigid);
  EXPECT_EQ(t.animation.transforms, fs::path("/jobs/bunny/rigid.txt"));
  EXPECT_EQ(t.animation.fps, 24.0);
  const Scene c = parse_patched(R"({"fracture": {"kind": "cuts", "mesh": "cuts.obj"}})");
  EXPECT_EQ(c.fracture.kind, FractureKind::cuts);
  EXPECT_EQ(c.fracture.cells_per_diagonal, 0.0);  // automatic
  const Scene pf = parse_patched(R"({"fracture": {"kind": "pieces", "mesh": "p.obj", "tolerance": 0.02, "cells_per_diagonal": 40}})");
  EXPECT_EQ(pf.fracture.tolerance, 0.02);
  EXPECT_EQ(pf.fracture.cells_per_diagonal, 40.0);
  EXPECT_EQ(parse_patched(R"({"fracture": {"kind": "pieces", "mesh": "p.obj"}})").fracture.tolerance, 0.005);
  EXPECT_EQ(parse_patched(R"({"fracture": {"kind": "cuts", "mesh": "c.obj", "cells_per_diagonal": 60}})").fracture.cells_per_diagonal,
            60.0);
  const Scene p = parse_patched(R"({"fracture": {"kind": "pieces", "mesh": "pieces.obj"}})");
  EXPECT_EQ(p.fracture.mesh, fs::path("/jobs/bunny/pieces.obj"));
  const Scene g = parse_patched(R"({"field": {"type": "grid", "resolution": null, "file": "s.raw"}})");
  EXPECT_EQ(g.field.type, FieldType::grid);
  EXPECT_EQ(g.field.file, fs::path("/jobs/bunny/s.raw"));
  EXPECT_EQ(g.field.resolution, glm::uvec3(0));
  const Scene f = parse_patched(R"({"pyramid": {"levels": 5.0}, "animation": {"kind": "frames", "frames": "f{}.txt",
                                    "count": 1}})");
  EXPECT_EQ(f.pyramid.levels, 5);  // 5.0 is accepted as an integer
  EXPECT_EQ(f.animation.first, 0);
  EXPECT_TRUE(f.animation.parent_map.empty());
}

class SceneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fracref_scene_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "jobs");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& text) {
    const fs::path p = dir_ / "jobs" / "scene.json";
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  fs::path dir_;
};

TEST_F(SceneFile, LoadsAndResolvesPathsAgainstTheScenesFolder) {
  const fs::path p = write(minimal().dump(2));
  const Scene s = load_scene(p);
  EXPECT_EQ(s.file, p);
  EXPECT_EQ(s.exterior, dir_ / "jobs" / "bunny.obj");
  EXPECT_TRUE(s.exterior.is_absolute());
  // A relative scene path still gives absolute, normal paths.
  const fs::path old = fs::current_path();
  fs::current_path(dir_);
  const Scene r = load_scene("jobs/../jobs/scene.json");
  fs::current_path(old);
  EXPECT_EQ(r.file, p);
  EXPECT_EQ(r.fracture.mesh, dir_ / "jobs" / "coarse.mesh");
}

TEST_F(SceneFile, MissingFileIsNamed) {
  const fs::path p = dir_ / "nothere.json";
  EXPECT_EQ(input_error([&] { load_scene(p); }), p.string() + ": file not found");
}

TEST_F(SceneFile, SyntaxErrorHasLineAndColumn) {
  const fs::path p = write("{\n  \"exterior\": \"bunny.obj\",\n  \"refine\": {\"tau\": 0.1,}\n}");
  EXPECT_EQ(input_error([&] { load_scene(p); }).rfind(p.string() + ":3:25: syntax error while parsing object key", 0),
            0u);
}

TEST_F(SceneFile, NestedDuplicateKeyIsNamed) {
  const fs::path p = write(R"({"exterior": "b.obj", "refine": {"tau": 0.1, "seed": 2, "tau": 0.2}})");
  EXPECT_EQ(input_error([&] { load_scene(p); }),
            p.string() + ": key 'refine.tau': duplicate key (a key may appear only once per object)");
}

TEST_F(SceneFile, OverflowIsNamed) {
  const fs::path p = write("{\"exterior\": \"b.obj\",\n \"refine\": {\"tau\": 1e999}}");
  EXPECT_EQ(input_error([&] { load_scene(p); }),
            p.string() + ":2:20: key 'refine.tau': number overflow parsing '1e999' (too large for a double)");
}

// A scene file too large to read whole is refused by its size (a sparse file: no disk, no memory).
TEST_F(SceneFile, HugeFileIsRefusedBySize) {
  const fs::path p = write("{");
  fs::resize_file(p, max_input_file_bytes() + 1);
  EXPECT_EQ(input_error([&] { load_scene(p); }).rfind(p.string() + ": the file is " + size_text(max_input_file_bytes() + 1), 0), 0u);
}

TEST(SceneErrors, OutOfRangeMatchesTheDocumentedFormat) {
  json j = minimal();
  j["refine"] = {{"tau", -1}};
  EXPECT_EQ(input_error([&] { parse_scene(j, "scene.json"); }), "scene.json: key 'refine.tau': must be in (0, 1), got -1");
}

TEST(SceneErrors, UnknownKeys) {
  EXPECT_EQ(patched_error(R"({"refnie": {}})").rfind(
                "/jobs/bunny/scene.json: key 'refnie': unknown key (did you mean 'refine'?); allowed keys: '$schema', "
                "'comment', 'name', 'exterior', 'fracture', 'animation', 'field', 'weights', 'pyramid', 'refine', "
                "'output'",
                0),
            0u);
  EXPECT_EQ(patched_error(R"({"refine": {"max_iteration": 3}})")
                .rfind("/jobs/bunny/scene.json: key 'refine.max_iteration': unknown key (did you mean 'max_iterations'?)",
                       0),
            0u);
  EXPECT_EQ(patched_error(R"({"output": {"png": true}})").rfind("/jobs/bunny/scene.json: key 'output.png': unknown key", 0),
            0u);
}

TEST(SceneErrors, MissingRequiredKeys) {
  EXPECT_EQ(patched_error(R"({"exterior": null})"), "/jobs/bunny/scene.json: key 'exterior': required key is missing");
  EXPECT_EQ(patched_error(R"({"fracture": null})"), "/jobs/bunny/scene.json: key 'fracture': required key is missing");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": null}})"),
            "/jobs/bunny/scene.json: key 'fracture.kind': required key is missing");
  EXPECT_EQ(patched_error(R"({"fracture": {"mesh": null}})"),
            "/jobs/bunny/scene.json: key 'fracture.mesh': required key is missing");
  EXPECT_EQ(patched_error(R"({"field": {"resolution": null}})"),
            "/jobs/bunny/scene.json: key 'field.resolution': required key is missing");
  EXPECT_EQ(patched_error(R"({"animation": {"kind": "frames", "frames": "f{}.txt"}})"),
            "/jobs/bunny/scene.json: key 'animation.count': required key is missing");
  EXPECT_EQ(patched_error(R"({"animation": {"kind": "rigid"}})"),
            "/jobs/bunny/scene.json: key 'animation.transforms': required key is missing");
}

TEST(SceneErrors, WrongTypes) {
  EXPECT_EQ(patched_error(R"({"refine": {"tau": "NaN"}})"),
            "/jobs/bunny/scene.json: key 'refine.tau': expected a number, got string \"NaN\" (JSON numbers cannot be NaN "
            "or infinite)");
  EXPECT_EQ(patched_error(R"({"pyramid": {"levels": 2.5}})"),
            "/jobs/bunny/scene.json: key 'pyramid.levels': expected an integer, got 2.5");
  EXPECT_EQ(patched_error(R"({"field": {"resolution": [50, 50.5, 50]}})"),
            "/jobs/bunny/scene.json: key 'field.resolution[1]': expected an integer, got 50.5");
  EXPECT_EQ(patched_error(R"({"refine": {"collisions": "yes"}})"),
            "/jobs/bunny/scene.json: key 'refine.collisions': expected true or false, got string \"yes\"");
  EXPECT_EQ(patched_error(R"({"exterior": 3})"), "/jobs/bunny/scene.json: key 'exterior': expected a string, got 3");
  EXPECT_EQ(patched_error(R"({"weights": 1})"), "/jobs/bunny/scene.json: key 'weights': expected an object, got 1");
  EXPECT_EQ(patched_error(R"({"comment": 1})"), "/jobs/bunny/scene.json: key 'comment': expected a string, got 1");
  EXPECT_EQ(patched_error(R"({"field": {"params": [1]}})"),
            "/jobs/bunny/scene.json: key 'field.params': expected an object, got an array");
}

TEST(SceneErrors, OutOfRange) {
  EXPECT_EQ(patched_error(R"({"refine": {"min_angle": 60}})"),
            "/jobs/bunny/scene.json: key 'refine.min_angle': must be in [0, 60), got 60");
  EXPECT_EQ(patched_error(R"({"refine": {"relax": 1.5}})"),
            "/jobs/bunny/scene.json: key 'refine.relax': must be in [0, 1], got 1.5");
  EXPECT_EQ(patched_error(R"({"refine": {"rim_smoothing": -1}})"),
            "/jobs/bunny/scene.json: key 'refine.rim_smoothing': must be an integer in [0, 1000], got -1");
  EXPECT_EQ(patched_error(R"({"refine": {"fold_solves": 0}})"),
            "/jobs/bunny/scene.json: key 'refine.fold_solves': must be an integer in [1, 8], got 0");
  EXPECT_EQ(patched_error(R"({"pyramid": {"levels": 9}})"),
            "/jobs/bunny/scene.json: key 'pyramid.levels': must be an integer in [1, 8], got 9");
  EXPECT_EQ(patched_error(R"({"field": {"resolution": [1, 50, 50]}})"),
            "/jobs/bunny/scene.json: key 'field.resolution[0]': must be an integer in [2, 1024], got 1");
  EXPECT_EQ(patched_error(R"({"weights": {"offset": 0}})"),
            "/jobs/bunny/scene.json: key 'weights.offset': must be in (0, 1e+06), got 0");
  EXPECT_EQ(patched_error(R"({"refine": {"max_triangles": 0}})"),
            "/jobs/bunny/scene.json: key 'refine.max_triangles': must be an integer in [1, 50000000], got 0");
  EXPECT_EQ(patched_error(R"({"output": {"preview_frames": 1001}})"),
            "/jobs/bunny/scene.json: key 'output.preview_frames': must be an integer in [0, 1000], got 1001");
  EXPECT_EQ(patched_error(R"({"output": {"frames_format": "ply"}})").rfind(
                "/jobs/bunny/scene.json: key 'output.frames_format': must be one of ", 0),
            0u);
  EXPECT_EQ(patched_error(R"({"animation": {"kind": "frames", "frames": "f{}.txt", "count": 0}})"),
            "/jobs/bunny/scene.json: key 'animation.count': must be an integer in [1, 1000000], got 0");
  EXPECT_EQ(patched_error(R"({"field": {"seed": -1}})"),
            "/jobs/bunny/scene.json: key 'field.seed': must be an integer >= 0, got -1");
  EXPECT_EQ(patched_error(R"({"weights": {"strength": 0, "distance": 0}})"),
            "/jobs/bunny/scene.json: key 'weights': 'strength' and 'distance' cannot both be 0 (the field would be "
            "constant)");
}

// Absurd padding and blur widths are refused by the scene, naming the file and the key, not later
// by the field or the pyramid without either.
TEST(SceneErrors, PaddingAndSigmaOutOfRange) {
  EXPECT_EQ(patched_error(R"({"field": {"padding": 1e308}})"),
            "/jobs/bunny/scene.json: key 'field.padding': must be in [0, 1], got 1e+308");
  EXPECT_EQ(patched_error(R"({"field": {"padding": -0.5}})"),
            "/jobs/bunny/scene.json: key 'field.padding': must be in [0, 1], got -0.5");
  EXPECT_EQ(patched_error(R"({"pyramid": {"sigma": 1e308}})"),
            "/jobs/bunny/scene.json: key 'pyramid.sigma': must be in (0, 20], got 1e+308");
  EXPECT_EQ(patched_error(R"({"pyramid": {"sigma": -1}})"),
            "/jobs/bunny/scene.json: key 'pyramid.sigma': must be in (0, 20], got -1");
  EXPECT_EQ(patched_error(R"({"pyramid": {"sigma": 0}})"),
            "/jobs/bunny/scene.json: key 'pyramid.sigma': must be in (0, 20], got 0");
  EXPECT_EQ(patched_error(R"({"pyramid": {"sigma": "NaN"}})"),
            "/jobs/bunny/scene.json: key 'pyramid.sigma': expected a number, got string \"NaN\" (JSON numbers cannot "
            "be NaN or infinite)");
  EXPECT_EQ(parse_patched(R"({"field": {"padding": 1}, "pyramid": {"sigma": 20}})").pyramid.sigma, 20.0);
}

TEST(SceneErrors, BadChoices) {
  EXPECT_EQ(patched_error(R"({"field": {"type": "marbel"}})"),
            "/jobs/bunny/scene.json: key 'field.type': must be one of 'marble', 'wood', 'branch', 'brick', "
            "'inclusions', 'perlin', 'fbm', 'constant', 'grid', got 'marbel' (did you mean 'marble'?)");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "tet"}})"),
            "/jobs/bunny/scene.json: key 'fracture.kind': must be one of 'tets', 'pieces', 'cuts', got 'tet' (did you "
            "mean 'tets'?)");
}

TEST(SceneErrors, InconsistentKeys) {
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "files": ["a.obj"]}})"),
            "/jobs/bunny/scene.json: key 'fracture.files': give either 'mesh' or 'files', not both");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "mesh": null}})"),
            "/jobs/bunny/scene.json: key 'fracture.mesh': required key is missing (or give 'files', one mesh file per "
            "piece)");
  EXPECT_EQ(patched_error(R"({"fracture": {"files": ["a.obj"]}})"),
            "/jobs/bunny/scene.json: key 'fracture.files': only allowed when kind is 'pieces' (use 'mesh')");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "cuts", "cracks": "c.txt"}})"),
            "/jobs/bunny/scene.json: key 'fracture.cracks': only allowed when kind is 'tets'");
  EXPECT_EQ(patched_error(R"({"fracture": {"cells_per_diagonal": 30}})"),
            "/jobs/bunny/scene.json: key 'fracture.cells_per_diagonal': only allowed when kind is 'cuts' or 'pieces'");
  EXPECT_EQ(patched_error(R"({"fracture": {"tolerance": 0.01}})"),
            "/jobs/bunny/scene.json: key 'fracture.tolerance': only allowed when kind is 'pieces'");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "mesh": "p.obj", "tolerance": 0.5}})"),
            "/jobs/bunny/scene.json: key 'fracture.tolerance': must be in (0, 0.1], got 0.5");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "mesh": "p.obj", "tolerance": 0}})"),
            "/jobs/bunny/scene.json: key 'fracture.tolerance': must be in (0, 0.1], got 0");
  EXPECT_NE(patched_error(R"({"fracture": {"kind": "cuts", "mesh": "c.obj", "cells_per_diagonal": 1e308}})")
                .find("key 'fracture.cells_per_diagonal'"),
            std::string::npos);
  EXPECT_EQ(patched_error(R"({"field": {"type": "grid", "resolution": null}})"),
            "/jobs/bunny/scene.json: key 'field.file': required key is missing");
  EXPECT_EQ(patched_error(R"({"field": {"file": "s.raw"}})"),
            "/jobs/bunny/scene.json: key 'field.file': only allowed when type is 'grid'");
  EXPECT_EQ(patched_error(R"({"animation": {"kind": "rigid", "transforms": "r.txt", "count": 3}})"),
            "/jobs/bunny/scene.json: key 'animation.count': only allowed when kind is 'frames'");
  EXPECT_EQ(patched_error(R"({"animation": {"kind": "frames", "frames": "f{}.txt", "count": 2, "transforms": "r"}})"),
            "/jobs/bunny/scene.json: key 'animation.transforms': only allowed when kind is 'rigid'");
}

TEST(SceneErrors, EmptyValues) {
  EXPECT_EQ(patched_error(R"({"exterior": ""})"), "/jobs/bunny/scene.json: key 'exterior': the path must not be empty");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "mesh": null, "files": []}})"),
            "/jobs/bunny/scene.json: key 'fracture.files': the array must not be empty");
  EXPECT_EQ(patched_error(R"({"fracture": {"kind": "pieces", "mesh": null, "files": ["a.obj", ""]}})"),
            "/jobs/bunny/scene.json: key 'fracture.files[1]': the path must not be empty");
  EXPECT_EQ(patched_error(R"({"name": ""})"), "/jobs/bunny/scene.json: key 'name': must not be empty");
}

TEST(SceneErrors, FramePatternNeedsOneField) {
  for (const char* bad : {"f.txt", "f{}{}.txt", "f{:4}.txt", "f{:04.txt", "f}{.txt", "f{x}.txt", "f{:0}.txt"}) {
    json patch = {{"animation", {{"kind", "frames"}, {"frames", bad}, {"count", 2}}}};
    EXPECT_EQ(patched_error(patch.dump()),
              "/jobs/bunny/scene.json: key 'animation.frames': must contain exactly one '{}' or '{:0N}' field for the "
              "frame number (N in 1..12), got '" +
                  std::string(bad) + "'");
  }
}

TEST(FramePath, ReplacesTheField) {
  EXPECT_EQ(frame_path("/a/frame_{:04}.txt", 7), fs::path("/a/frame_0007.txt"));
  EXPECT_EQ(frame_path("/a/frame_{:02}.txt", 12345), fs::path("/a/frame_12345.txt"));
  EXPECT_EQ(frame_path("/a/{}/f.txt", 12), fs::path("/a/12/f.txt"));
}

TEST(SceneEnums, Names) {
  EXPECT_STREQ(to_string(FractureKind::cuts), "cuts");
  EXPECT_STREQ(to_string(AnimationKind::rigid), "rigid");
  EXPECT_STREQ(to_string(FieldType::inclusions), "inclusions");
  EXPECT_STREQ(to_string(FieldType::grid), "grid");
}

/// The json blocks of scenes/SCHEMA.md: the complete example first, then the smallest scene.
std::vector<std::string> schema_examples() {
  const fs::path doc = fs::path(FRACREF_SOURCE_DIR) / "scenes" / "SCHEMA.md";
  std::ifstream in(doc);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::string open = "```json\n";
  std::vector<std::string> blocks;
  for (auto begin = text.find(open); begin != std::string::npos; begin = text.find(open, begin + 1)) {
    const auto end = text.find("```", begin + open.size());
    if (end == std::string::npos) break;
    blocks.push_back(text.substr(begin + open.size(), end - begin - open.size()));
  }
  return blocks;
}

/// The examples in scenes/SCHEMA.md must stay valid scenes.
TEST(SchemaDoc, ExamplesAreValid) {
  const std::vector<std::string> blocks = schema_examples();
  ASSERT_EQ(blocks.size(), 2u);
  const Scene s = parse_scene(parse_json_strict(blocks[0], "SCHEMA.md"), "/jobs/bunny/scene.json");
  EXPECT_EQ(s.name, "marble bunny");
  EXPECT_EQ(s.fracture.kind, FractureKind::tets);
  EXPECT_EQ(s.fracture.cracks, fs::path("/jobs/bunny/bunny_cracks.txt"));
  EXPECT_EQ(s.animation.kind, AnimationKind::frames);
  EXPECT_EQ(s.animation.count, 48);
  EXPECT_EQ(s.field.type, FieldType::marble);
  EXPECT_EQ(s.field.resolution, glm::uvec3(50, 50, 50));
  const Scene m = parse_scene(parse_json_strict(blocks[1], "SCHEMA.md"), "/jobs/bunny/scene.json");
  EXPECT_EQ(m.fracture.files.size(), 2u);
  EXPECT_EQ(m.field.resolution, glm::uvec3(32, 32, 64));
}

}  // namespace
}  // namespace fracref
