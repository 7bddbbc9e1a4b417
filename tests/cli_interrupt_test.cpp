// A run interrupted by SIGINT or SIGTERM removes its staging folders and exits with 128 + the
// signal; one killed outright (SIGKILL) leaves them, and the next run into the same output removes
// them. The previous output stays intact throughout.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <thread>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;

namespace {

// Starts `fracref demo wall -o OUT` (made slow by a fine tau), waits until its staging folder
// exists, sends `sig`, and returns the exit status.
int interrupted_run(const fs::path& out, int sig) {
  const pid_t child = fork();
  if (child == 0) {
    execl(FRACREF_EXE, FRACREF_EXE, "demo", "wall", "-o", out.c_str(), "--backend", "cpu", "-q", "--set",
          "refine.tau=1e-9", static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path staging = out.string() + ".tmp-" + std::to_string(child);
  for (int i = 0; i < 600 && !fs::exists(staging); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(child, sig);
  int status = 0;
  waitpid(child, &status, 0);
  return status;
}

// Starts `fracref refine SCENE -o OUT` (made slow by a fine tau), waits until it has written a
// file of its own output (the staging folder holds coarse_surface.ply), sends `sig`, and returns
// the exit status.
int interrupted_while_writing(const fs::path& scene, const fs::path& out, int sig) {
  const pid_t child = fork();
  if (child == 0) {
    execl(FRACREF_EXE, FRACREF_EXE, "refine", scene.c_str(), "-o", out.c_str(), "--backend", "cpu", "-q", "--set",
          "refine.tau=1e-9", static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path written = out.string() + ".tmp-" + std::to_string(child) + "/coarse_surface.ply";
  for (int i = 0; i < 1200 && !fs::exists(written); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(child, sig);
  int status = 0;
  waitpid(child, &status, 0);
  return status;
}

// Every file under `dir` by relative path, with its bytes.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

// The scene file of a demo's output (OUT/input/NAME.json).
fs::path demo_scene_file(const fs::path& input) {
  for (const auto& e : fs::directory_iterator(input))
    if (e.path().extension() == ".json") return e.path();
  return {};
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(CliInterrupt, SigintAndSigtermCleanUpAndKeepThePreviousOutput) {
  TempDir t;
  const fs::path out = t.path / "out";
  ASSERT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  const std::string before = slurp(out / "report.json");
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    const int status = interrupted_run(out, sig);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_EQ(entries(t.path), std::vector<std::string>{"out"});  // no staging folder left
    EXPECT_EQ(slurp(out / "report.json"), before);
  }
}

TEST(CliInterrupt, AfterSigkillTheNextRunRemovesTheStagingFolders) {
  TempDir t;
  const fs::path out = t.path / "out";
  ASSERT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  const std::string before = slurp(out / "report.json");
  const int status = interrupted_run(out, SIGKILL);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_GT(entries(t.path).size(), 1u);  // it left its staging folders
  EXPECT_EQ(slurp(out / "report.json"), before);
  ASSERT_EQ(run("demo branch -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  EXPECT_EQ(entries(t.path), std::vector<std::string>{"out"});
}

// A refine into an existing output folder, interrupted after it has started writing the new
// output: the previous output stays whole, file for file, and no staging folder is left (after
// the next run, for SIGKILL, which nothing can catch).
TEST(CliInterrupt, InterruptedWhileWritingKeepsEveryFileOfThePreviousOutput) {
  TempDir t;
  const fs::path out = t.path / "out";
  ASSERT_EQ(run("demo wall -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  fs::copy(out / "input", t.path / "scene", fs::copy_options::recursive);
  const fs::path scene = demo_scene_file(t.path / "scene");
  ASSERT_FALSE(scene.empty());
  const auto before = tree(out);
  ASSERT_GT(before.size(), 2u);
  for (int sig : {SIGINT, SIGKILL}) {
    SCOPED_TRACE(sig);
    const int status = interrupted_while_writing(scene, out, sig);
    if (sig == SIGKILL) {
      ASSERT_TRUE(WIFSIGNALED(status));
    } else {
      ASSERT_TRUE(WIFEXITED(status));
      EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
      EXPECT_EQ(entries(t.path), (std::vector<std::string>{"out", "scene"}));
    }
    EXPECT_EQ(tree(out), before);
  }
  ASSERT_EQ(run("refine " + scene.string() + " -o " + out.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  EXPECT_EQ(entries(t.path), (std::vector<std::string>{"out", "scene"}));
  EXPECT_TRUE(fs::exists(out / "coarse_surface.ply"));
}
