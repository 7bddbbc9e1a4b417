// `fracref batch` as a user runs it: three small cube jobs and one malformed scene on the CPU
// backend (no Vulkan driver visible), run as child processes at most two at once; the rerun
// skips what finished; the summary's CSV and JSON; manifest errors name the key.
#include <gtest/gtest.h>

#include "cube_scene.hpp"
#include <sys/stat.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_support.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const char* kNoVulkan = "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent";

using test_scenes::cube_mesh;
const char* const kCube = test_scenes::kCubeObj;

/// The cube scene, a malformed one (refine.tau < 0), and a manifest of 3 good jobs and the bad.
void write_inputs(const TempDir& t) {
  t.write("in/cube.obj", kCube);
  t.write("in/cube.mesh", cube_mesh(2));
  t.write("in/cube.json", R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
      "field": {"type": "marble", "resolution": [16, 16, 16]},
      "refine": {"max_iterations": 3, "max_triangles": 2000}})");
  t.write("in/bad.json", R"({"exterior": "cube.obj", "fracture": {"kind": "tets", "mesh": "cube.mesh"},
      "field": {"type": "marble", "resolution": [16, 16, 16]}, "refine": {"tau": -1}})");
  t.write("m.json", R"({"comment": "three cube jobs and a malformed scene",
      "defaults": {"backend": "cpu", "stop_after": "refine"},
      "jobs": [{"scene": "in/cube.json", "sweep": {"seed": [1, 2]}},
               {"scene": "in/cube.json", "id": "tau", "refine.tau": 0.004},
               {"scene": "in/bad.json"}]})");
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

}  // namespace

TEST(CliBatch, GoodJobsFinishTheBadOneFailsWithItsMessageAndTheRerunSkips) {
  TempDir t;
  write_inputs(t);
  const fs::path out = t.path / "out";
  auto r = run("batch " + (t.path / "m.json").string() + " -j 2 -o " + out.string(), kNoVulkan);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("3 ok, 1 failed, 0 crashed, 0 skipped"), std::string::npos) << r.err;
  for (const char* id : {"cube-seed=1", "cube-seed=2", "tau"}) {
    const fs::path job = out / "jobs" / id;
    EXPECT_TRUE(fs::exists(job / "output" / "report.json")) << id << "\n" << slurp(job / "log.txt");
    EXPECT_TRUE(fs::exists(job / "output" / "fracture_surface.ply")) << id;
    EXPECT_EQ(json::parse(slurp(job / "status.json"))["status"], "ok") << id;
    EXPECT_NE(slurp(job / "log.txt").find(" refine "), std::string::npos) << id;
  }
  EXPECT_NE(slurp(out / "jobs/cube-seed=2/log.txt").find("--seed 2"), std::string::npos);
  const json tau_scene = json::parse(slurp(out / "jobs/tau/scene.json"));
  EXPECT_EQ(tau_scene["refine"]["tau"], 0.004);
  EXPECT_EQ(tau_scene["refine"]["max_iterations"], 3);
  const std::string bad_log = slurp(out / "jobs/bad/log.txt");
  EXPECT_NE(bad_log.find("bad.json: key 'refine.tau': must be in (0, 1)"), std::string::npos) << bad_log;
  EXPECT_FALSE(fs::exists(out / "jobs/bad/output"));
  EXPECT_EQ(json::parse(slurp(out / "jobs/bad/status.json"))["exit_code"], 2);

  const auto csv = lines_of(slurp(out / "summary.csv"));
  ASSERT_EQ(csv.size(), 5u) << slurp(out / "summary.csv");
  EXPECT_EQ(csv[0], "id,scene,overrides,status,exit_code,signal,seconds,job_seconds,coarse_triangles,refined_triangles,message");
  EXPECT_EQ(csv[1].rfind("cube-seed=1,in/cube.json,seed=1 stop_after=refine backend=cpu,ok,0,,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[2].rfind("cube-seed=2,in/cube.json,seed=2 stop_after=refine backend=cpu,ok,0,,", 0), 0u) << csv[2];
  EXPECT_EQ(csv[3].rfind("tau,in/cube.json,stop_after=refine backend=cpu refine.tau=0.004,ok,0,,", 0), 0u) << csv[3];
  EXPECT_EQ(csv[4].rfind("bad,in/bad.json,stop_after=refine backend=cpu,failed,2,,", 0), 0u) << csv[4];
  EXPECT_NE(csv[4].find("key 'refine.tau': must be in (0, 1)"), std::string::npos) << csv[4];
  EXPECT_NE(csv[1].find(",8,"), std::string::npos) << csv[1];  // 8 coarse triangles
  const json summary = json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["success"], false);
  EXPECT_EQ(summary["counts"]["ok"], 3);
  EXPECT_EQ(summary["counts"]["failed"], 1);
  EXPECT_EQ(summary["jobs"][0]["coarse_triangles"], 8);
  EXPECT_EQ(summary["jobs"][2]["overrides"]["refine.tau"], 0.004);
  EXPECT_EQ(summary["jobs"][3]["status"], "failed");

  // Rerun: the finished jobs are skipped (their outputs untouched), the bad one runs again.
  struct stat before {};
  ::stat((out / "jobs/tau/output/report.json").c_str(), &before);
  const std::string log_before = slurp(out / "jobs/tau/log.txt");
  r = run("batch " + (t.path / "m.json").string() + " -j 2 -o " + out.string() + " -q", kNoVulkan);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("0 ok, 1 failed, 0 crashed, 3 skipped"), std::string::npos) << r.err;
  struct stat after {};
  ::stat((out / "jobs/tau/output/report.json").c_str(), &after);
  EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
  EXPECT_EQ(slurp(out / "jobs/tau/log.txt"), log_before);
  const auto csv2 = lines_of(slurp(out / "summary.csv"));
  ASSERT_EQ(csv2.size(), 5u);
  EXPECT_NE(csv2[1].find(",skipped,0,"), std::string::npos) << csv2[1];
  EXPECT_NE(csv2[4].find(",failed,2,"), std::string::npos) << csv2[4];
}

TEST(CliBatch, ListAndIndexSelectOneJob) {
  TempDir t;
  write_inputs(t);
  auto r = run("batch " + (t.path / "m.json").string() + " --list");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "cube-seed=1\ncube-seed=2\ntau\nbad\n");
  const fs::path out = t.path / "out";
  r = run("batch " + (t.path / "m.json").string() + " --index 1 -q -o " + out.string(), kNoVulkan);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "jobs/cube-seed=2/output/report.json"));
  EXPECT_FALSE(fs::exists(out / "jobs/cube-seed=1"));
  const json summary = json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["counts"]["ok"], 1);
  EXPECT_EQ(summary["counts"]["pending"], 3);
  r = run("batch " + (t.path / "m.json").string() + " --index 4 -o " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--index 4"), std::string::npos) << r.err;
}

TEST(CliBatch, ManifestErrorsNameTheKeyAndRunNothing) {
  TempDir t;
  write_inputs(t);
  struct Case {
    std::string manifest, expect;
  } cases[] = {
      {R"({"jobs": [{"scene": "in/cube.json", "backnd": "cpu"}]})", "key 'jobs[0].backnd': unknown key (did you mean 'backend'?)"},
      {R"({"jobs": [{"scene": "in/cube.json", "sweep": {"seed": 3}}]})", "key 'jobs[0].sweep.seed': must be a non-empty array"},
      {R"({"jobs": [{"scene": "in/cube.json", "sweep": {"refine.tau": [0.1, "x"]}}, {"demo": "wal"}]})", "key 'jobs[1].demo'"},
      {R"({"jobs": [{"scene": "in/cube.json"}, )", "bad.json:1:"},
  };
  for (const Case& c : cases) {
    const auto m = t.write("bad.json", c.manifest);
    auto r = run("batch " + m.string() + " -o " + (t.path / "never").string());
    EXPECT_EQ(r.code, 2) << c.manifest << "\n" << r.err;
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(t.path / "never"));
  }
}
