// animation.glb as a user gets it: the branch demo writes it, `fracref check`
// verifies it and names a damaged one (exit 1), and a scene with output.glb false writes none.
#include <gtest/gtest.h>

#include <cstdint>

#include "cli_support.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
namespace fs = std::filesystem;

TEST(CliGlb, DemoWritesACheckedGlbAndCheckNamesADamagedOne) {
  TempDir t;
  const fs::path out = t.path / "branch";
  auto r = run("demo branch -o " + out.string() + " --backend cpu -q --set refine.tau=0.002 --set refine.delta=0.004");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string glb = slurp(out / "animation.glb");
  ASSERT_GE(glb.size(), 12u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  EXPECT_NE(slurp(out / "report.json").find("\"glb\": {\n    \"bytes\": " + std::to_string(glb.size())), std::string::npos);
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("passed  glb: 2 nodes"), std::string::npos) << r.out;

  std::ofstream(out / "animation.glb", std::ios::binary) << glb.substr(0, glb.size() - 4);
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("failed  glb"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("animation.glb: header length " + std::to_string(glb.size()) + ", the file has " +
                       std::to_string(glb.size() - 4) + " bytes"),
            std::string::npos)
      << r.err;
}

TEST(CliGlb, OutputGlbFalseWritesNone) {
  TempDir t;
  const fs::path first = t.path / "first";
  ASSERT_EQ(run("demo branch -o " + first.string() + " --backend cpu -q --stop-after preprocess").code, 0);
  std::string scene = slurp(first / "input" / "branch.json");
  const std::size_t at = scene.find("\"refine\"");
  ASSERT_NE(at, std::string::npos) << scene;
  scene.insert(at, "\"output\": {\"glb\": false},\n  ");
  const fs::path path = first / "input" / "no_glb.json";
  std::ofstream(path, std::ios::binary) << scene;
  const fs::path out = t.path / "out";
  auto r = run("refine " + path.string() + " -o " + out.string() +
               " --backend cpu -q --set refine.tau=0.002 --set refine.delta=0.004");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / "frames"));  // off by default
  EXPECT_FALSE(fs::exists(out / "animation.glb"));
  r = run("check " + out.string());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("skipped  glb"), std::string::npos) << r.out;
}
