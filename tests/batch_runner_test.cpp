// The batch runner with a stand-in for the fracref binary (a shell script that succeeds, fails or
// kills itself depending on a marker in the scene file): outcomes, logs, status files, summary,
// resumability, the parallel limit, --only, and scenes rewritten for overrides.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "batch/runner.hpp"
#include "scene/json_strict.hpp"
#include "util/error.hpp"

using namespace fracref;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Arguments: refine SCENE | demo NAME, then -o OUT and other options. The scene's text decides:
// FAIL exits 2 with a message, CRASH kills itself with SIGSEGV, anything else writes a report.
// Every run appends its scene and arguments to calls.txt and its concurrency to running.txt.
const char* kFakeExe = R"(#!/bin/sh
dir=$(dirname "$0")
echo "$*" >> "$dir/calls.txt"
what=$2
shift 2
out=""
while [ $# -gt 0 ]; do
  if [ "$1" = "-o" ]; then out=$2; shift; fi
  shift
done
mkdir "$dir/lock.$$"
ls -d "$dir"/lock.* | wc -l >> "$dir/running.txt"
sleep 0.2
rmdir "$dir/lock.$$"
echo "fake: running $what"
if [ -f "$what" ] && grep -q FAIL "$what"; then echo "fake: $what: key 'refine.tau': must be > 0, got -1" >&2; exit 2; fi
if [ -f "$what" ] && grep -q CRASH "$what"; then kill -s SEGV $$; fi
mkdir -p "$out"
echo '{"seconds": {"total": 1.5}, "coarse_triangles": 8, "refined_triangles": 20}' > "$out/report.json"
exit 0
)";

struct Fixture {
  fs::path dir;
  Fixture() {
    static int n = 0;
    dir = fs::temp_directory_path() / ("fracref_batch_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(dir);
    fs::create_directories(dir / "bin");
    write("bin/fracref", kFakeExe);
    ::chmod((dir / "bin/fracref").c_str(), 0755);
  }
  ~Fixture() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
  }
  /// A scene that parses (the files it names are never opened here), with a marker comment.
  fs::path scene(const std::string& name, const std::string& marker) const {
    return write(name + ".json", R"({"comment": ")" + marker + R"(", "exterior": "cube.obj",
      "fracture": {"kind": "tets", "mesh": "cube.mesh"}, "field": {"type": "marble", "resolution": [8, 8, 8]}})");
  }
  Manifest manifest(const std::string& text) const {
    write("m.json", text);
    return load_manifest(dir / "m.json", {"wall", "clay"});
  }
  BatchRunOptions options(int parallel = 2) const {
    BatchRunOptions o;
    o.exe = dir / "bin/fracref";
    o.out = dir / "out";
    o.parallel = parallel;
    o.backend = "cpu";
    return o;
  }
  std::vector<std::string> calls() const {
    std::vector<std::string> lines;
    std::istringstream in(slurp(dir / "bin/calls.txt"));
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
};

}  // namespace

TEST(BatchRunner, OkFailedAndCrashedJobsAreRecordedAndTheOthersGoOn) {
  Fixture f;
  f.scene("good", "fine");
  f.scene("bad", "FAIL");
  f.scene("boom", "CRASH");
  Manifest m = f.manifest(R"({"jobs": [{"scene": "bad.json"}, {"scene": "boom.json"}, {"scene": "good.json", "seed": 4}]})");
  BatchResult r = run_batch(m, f.options());
  ASSERT_EQ(r.jobs.size(), 3u);
  EXPECT_FALSE(r.success());
  EXPECT_EQ(r.jobs[0].status, JobStatus::failed);
  EXPECT_EQ(r.jobs[0].exit_code, 2);
  EXPECT_NE(r.jobs[0].message.find("key 'refine.tau'"), std::string::npos) << r.jobs[0].message;
  EXPECT_EQ(r.jobs[1].status, JobStatus::crashed);
  EXPECT_FALSE(r.jobs[1].exit_code.has_value());
  EXPECT_EQ(r.jobs[1].signal, SIGSEGV);
  EXPECT_NE(r.jobs[1].message.find("killed by signal 11"), std::string::npos) << r.jobs[1].message;
  EXPECT_EQ(r.jobs[2].status, JobStatus::ok);
  EXPECT_EQ(r.jobs[2].exit_code, 0);
  EXPECT_EQ(r.jobs[2].coarse_triangles, 8u);
  EXPECT_EQ(r.jobs[2].refined_triangles, 20u);
  EXPECT_EQ(r.jobs[2].job_seconds, 1.5);
  for (const JobOutcome& o : r.jobs) EXPECT_GE(o.seconds, 0.2);  // each child sleeps 0.2 s
  const fs::path good = job_folder(f.dir / "out", "good");
  const std::string log = slurp(good / "log.txt");
  EXPECT_EQ(log.rfind("$ " + (f.dir / "bin/fracref").string() + " refine " + (f.dir / "good.json").string() + " -o " +
                          (good / "output").string() + " --backend cpu --seed 4\n",
                      0),
            0u)
      << log;
  EXPECT_NE(log.find("fake: running"), std::string::npos);
  EXPECT_NE(slurp(job_folder(f.dir / "out", "bad") / "log.txt").find("must be > 0"), std::string::npos);
  EXPECT_NE(slurp(job_folder(f.dir / "out", "boom") / "log.txt").find("killed by signal"), std::string::npos);
  EXPECT_EQ(read_json_file(good / "status.json")["status"], "ok");
  EXPECT_EQ(read_json_file(job_folder(f.dir / "out", "boom") / "status.json")["signal"], SIGSEGV);

  write_batch_summary(m, r, f.dir / "out");
  const std::string csv = slurp(f.dir / "out/summary.csv");
  std::istringstream lines(csv);
  std::string header, bad, boom, ok;
  std::getline(lines, header), std::getline(lines, bad), std::getline(lines, boom), std::getline(lines, ok);
  EXPECT_EQ(header, "id,scene,overrides,status,exit_code,signal,seconds,job_seconds,coarse_triangles,refined_triangles,message");
  EXPECT_EQ(bad.rfind("bad,bad.json,,failed,2,,", 0), 0u) << bad;
  EXPECT_NE(bad.find(",,,\"fake: "), std::string::npos) << bad;  // quoted: the message has a quote
  EXPECT_EQ(boom.rfind("boom,boom.json,,crashed,,11,", 0), 0u) << boom;
  EXPECT_EQ(ok.rfind("good,good.json,seed=4,ok,0,,", 0), 0u) << ok;
  EXPECT_NE(ok.find(",1.500,8,20,"), std::string::npos) << ok;
  const json summary = read_json_file(f.dir / "out/summary.json");
  EXPECT_EQ(summary["success"], false);
  EXPECT_EQ(summary["counts"]["ok"], 1);
  EXPECT_EQ(summary["counts"]["failed"], 1);
  EXPECT_EQ(summary["counts"]["crashed"], 1);
  EXPECT_EQ(summary["jobs"][2]["overrides"]["seed"], 4);
  EXPECT_EQ(summary["jobs"][2]["refined_triangles"], 20);
  EXPECT_EQ(summary["jobs"][1]["exit_code"], nullptr);
}

TEST(BatchRunner, RerunSkipsCompleteJobsUnlessTheJobChanged) {
  Fixture f;
  f.scene("a", "fine");
  f.scene("b", "fine");
  f.scene("bad", "FAIL");
  const std::string text = R"({"jobs": [{"scene": "a.json"}, {"scene": "b.json"}, {"scene": "bad.json"}]})";
  BatchResult first = run_batch(f.manifest(text), f.options());
  EXPECT_EQ(first.count(JobStatus::ok), 2u);
  EXPECT_EQ(f.calls().size(), 3u);
  BatchResult second = run_batch(f.manifest(text), f.options());
  EXPECT_EQ(second.jobs[0].status, JobStatus::skipped);
  EXPECT_EQ(second.jobs[1].status, JobStatus::skipped);
  EXPECT_EQ(second.jobs[1].refined_triangles, 20u);
  EXPECT_EQ(second.jobs[2].status, JobStatus::failed);  // failed jobs run again
  EXPECT_EQ(f.calls().size(), 4u);
  // A changed job (here its seed) is not the job that completed: it runs again.
  BatchResult third = run_batch(f.manifest(R"({"jobs": [{"scene": "a.json", "seed": 9}, {"scene": "b.json"}]})"), f.options());
  EXPECT_EQ(third.jobs[0].status, JobStatus::ok);
  EXPECT_EQ(third.jobs[1].status, JobStatus::skipped);
  ASSERT_EQ(f.calls().size(), 5u);
  EXPECT_NE(f.calls()[4].find("--seed 9"), std::string::npos);
  // An output without its report (an interrupted run) is not complete either.
  fs::remove(job_folder(f.dir / "out", "b") / "output" / "report.json");
  EXPECT_EQ(run_batch(f.manifest(text), f.options()).jobs[1].status, JobStatus::ok);
}

TEST(BatchRunner, NeverRunsMoreThanTheParallelLimit) {
  for (int limit : {1, 2}) {
    Fixture f;
    f.scene("s", "fine");
    Manifest m = f.manifest(R"({"jobs": [{"scene": "s.json", "sweep": {"seed": [1, 2, 3, 4, 5]}}]})");
    BatchResult r = run_batch(m, f.options(limit));
    EXPECT_EQ(r.count(JobStatus::ok), 5u);
    std::istringstream in(slurp(f.dir / "bin/running.txt"));
    int most = 0, n = 0, runs = 0;
    while (in >> n) most = std::max(most, n), ++runs;
    EXPECT_EQ(runs, 5);
    EXPECT_LE(most, limit);
    EXPECT_GE(most, 1);
  }
}

TEST(BatchRunner, OnlyAndSummaryOnlyReportTheOtherJobsFromTheirFolders) {
  Fixture f;
  f.scene("s", "fine");
  Manifest m = f.manifest(R"({"jobs": [{"scene": "s.json", "sweep": {"seed": [1, 2, 3]}}]})");
  BatchRunOptions o = f.options();
  o.only = {"s-seed=2"};
  BatchResult r = run_batch(m, o);
  EXPECT_EQ(r.jobs[0].status, JobStatus::pending);
  EXPECT_EQ(r.jobs[1].status, JobStatus::ok);
  EXPECT_EQ(r.jobs[2].status, JobStatus::pending);
  EXPECT_TRUE(r.success());
  o.only = {};
  o.summary_only = true;
  r = run_batch(m, o);
  EXPECT_EQ(r.jobs[1].status, JobStatus::skipped);
  EXPECT_EQ(r.jobs[0].status, JobStatus::pending);
  EXPECT_EQ(f.calls().size(), 1u);
  o.summary_only = false;
  o.only = {"s-seed=7"};
  try {
    run_batch(m, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no job has the id 's-seed=7'"), std::string::npos) << e.what();
  }
}

TEST(BatchRunner, AMissingProgramFailsEveryJobWithTheReason) {
  Fixture f;
  f.scene("s", "fine");
  BatchRunOptions o = f.options();
  o.exe = f.dir / "bin/missing";
  BatchResult r = run_batch(f.manifest(R"({"jobs": [{"scene": "s.json"}]})"), o);
  EXPECT_EQ(r.jobs[0].status, JobStatus::failed);
  EXPECT_NE(r.jobs[0].message.find("cannot start"), std::string::npos) << r.jobs[0].message;
}

TEST(BatchRunner, OverridesRunARewrittenSceneAndBadOnesFailBeforeStarting) {
  Fixture f;
  f.scene("s", "fine");
  Manifest m = f.manifest(R"({"jobs": [{"scene": "s.json", "refine.tau": 0.01, "id": "good"},
                                       {"scene": "s.json", "refine.tua": 0.01, "id": "typo"}]})");
  BatchResult r = run_batch(m, f.options());
  EXPECT_EQ(r.jobs[0].status, JobStatus::ok);
  const fs::path folder = job_folder(f.dir / "out", "good");
  const json scene = read_json_file(folder / "scene.json");
  EXPECT_EQ(scene["refine"]["tau"], 0.01);
  EXPECT_EQ(scene["exterior"], (f.dir / "cube.obj").string());
  EXPECT_EQ(scene["fracture"]["mesh"], (f.dir / "cube.mesh").string());
  EXPECT_EQ(scene["name"], "s");
  ASSERT_EQ(f.calls().size(), 1u);
  EXPECT_EQ(f.calls()[0].rfind("refine " + (folder / "scene.json").string(), 0), 0u) << f.calls()[0];
  EXPECT_EQ(r.jobs[1].status, JobStatus::failed);
  EXPECT_EQ(r.jobs[1].exit_code, 2);
  const std::string log = slurp(job_folder(f.dir / "out", "typo") / "log.txt");
  EXPECT_NE(log.find((f.dir / "s.json").string() + ": key 'refine.tua': unknown key"), std::string::npos) << log;
  EXPECT_NE(r.jobs[1].message.find("refine.tua"), std::string::npos);
}

TEST(BatchRunner, DemoJobsRunTheDemoCommandOrAGeneratedSceneForOverrides) {
  Fixture f;
  Manifest m = f.manifest(R"({"jobs": [{"demo": "wall", "stop_after": "refine"},
                                       {"demo": "clay", "sweep": {"refine.max_iterations": [1, 2]}}]})");
  BatchRunOptions o = f.options(1);
  int generated = 0;
  o.generate_demo = [&](const std::string& name, const fs::path& folder) {
    ++generated;
    std::ofstream(folder / (name + ".json")) << R"({"exterior": "clay.obj", "fracture": {"kind": "tets", "mesh": "clay.mesh"},
                                                  "field": {"type": "marble", "resolution": [8, 8, 8]}})";
    return folder / (name + ".json");
  };
  BatchResult r = run_batch(m, o);
  EXPECT_EQ(r.count(JobStatus::ok), 3u);
  EXPECT_EQ(generated, 1);
  const auto calls = f.calls();
  ASSERT_EQ(calls.size(), 3u);
  EXPECT_EQ(calls[0].rfind("demo wall -o ", 0), 0u) << calls[0];
  EXPECT_NE(calls[0].find("--stop-after refine"), std::string::npos) << calls[0];
  EXPECT_EQ(calls[1].rfind("refine " + (job_folder(f.dir / "out", "clay-refine.max_iterations=1") / "scene.json").string(), 0), 0u)
      << calls[1];
  const json scene = read_json_file(job_folder(f.dir / "out", "clay-refine.max_iterations=2") / "scene.json");
  EXPECT_EQ(scene["refine"]["max_iterations"], 2);
  EXPECT_EQ(scene["exterior"], (f.dir / "out/inputs/clay/clay.obj").string());
  EXPECT_EQ(scene["name"], "clay");
}
