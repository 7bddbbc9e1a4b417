// `fracref bench` as a user runs it, on small invocations: the JSON's and the Markdown's
// structure, an unavailable Vulkan saying why while the CPU still runs, the bunny skipped
// without its mesh, bad options. No timing is asserted.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "util/parallel.hpp"

using cli_test::run;
using cli_test::slurp;
using cli_test::TempDir;
using nlohmann::json;

namespace {
const char* kNoVulkan = "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent";
}

TEST(CliBench, KernelsOnlyWritesOneEntryPerKernelSizeAndBackend) {
  TempDir t;
  const auto file = t.path / "bench.json";
  auto r = run("bench --kernels-only --backends cpu --repeat 2 --kernel-sizes 400,900 -q --json " + file.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(slurp(file));
  EXPECT_EQ(j["repeat"], 2);
  EXPECT_EQ(j["results"].size(), 0u);
  EXPECT_EQ(j["backends"]["cpu"]["name"], "cpu");
  const char* kernels[] = {"pyramid", "call_k1k2", "call_k3", "k1k2", "k3", "k1k2", "k3"};
  const int sizes[] = {262144, 9, 9, 400, 400, 900, 900};
  ASSERT_EQ(j["kernels"].size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    const json& k = j["kernels"][i];
    EXPECT_EQ(k["kernel"], kernels[i]);
    EXPECT_EQ(k["size"], sizes[i]);
    EXPECT_EQ(k["backend"], "cpu");
    EXPECT_EQ(k["samples_ms"].size(), 2u);
    EXPECT_TRUE(k["median_ms"].is_number());
    EXPECT_GE(k["calls_per_sample"].get<int>(), 1);
    EXPECT_FALSE(k.contains("error"));
  }
  EXPECT_NE(r.out.find("k1k2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cpu ms"), std::string::npos) << r.out;
}

TEST(CliBench, KernelsOnlyMarkdownNamesTheCommandAsGiven) {
  TempDir t;
  const auto md_file = t.path / "k.md";
  auto r = run("bench --kernels-only --backends cpu --repeat 2 --kernel-sizes 400 -q --markdown " + md_file.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = slurp(md_file);
  EXPECT_NE(md.find("`fracref bench --backends cpu --repeat 2 --kernels-only --kernel-sizes 400`"), std::string::npos) << md;
  EXPECT_EQ(md.find("--scenes"), std::string::npos) << md;
}

TEST(CliBench, ScenesWithoutVulkanSayWhyAndTheCpuStillRuns) {
  TempDir t;
  const auto file = t.path / "bench.json";
  const auto markdown = t.path / "bench.md";
  auto r = run("bench --scenes wall --backends cpu,vulkan --repeat 2 --no-kernels --stop-after preprocess --json " +
                   file.string() + " --markdown " + markdown.string(),
               kNoVulkan);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(slurp(file));
  EXPECT_EQ(j["stop_after"], "preprocess");
  EXPECT_EQ(j["kernels"].size(), 0u);
  ASSERT_EQ(j["results"].size(), 2u);
  const json& cpu = j["results"][0];
  EXPECT_EQ(cpu["scene"], "wall");
  EXPECT_EQ(cpu["backend"], "cpu");
  EXPECT_EQ(cpu["runs"], 2);
  EXPECT_EQ(cpu["samples_seconds"]["setup"].size(), 2u);
  EXPECT_EQ(cpu["samples_seconds"]["total"].size(), 2u);
  EXPECT_TRUE(cpu["median_seconds"]["total"].is_number());
  EXPECT_GT(cpu["coarse_triangles"].get<int>(), 0);
  EXPECT_EQ(cpu["paper_seconds"], 13.6);
  EXPECT_GT(cpu["paper_triangles"]["refined"].get<int>(), 100000);
  const json& vk = j["results"][1];
  EXPECT_EQ(vk["backend"], "vulkan");
  EXPECT_EQ(vk["error"].get<std::string>().rfind("unavailable: ", 0), 0u) << vk["error"];
  EXPECT_EQ(vk["runs"], 0);
  EXPECT_TRUE(j["backends"]["vulkan"].contains("unavailable"));
  ASSERT_EQ(j["comparisons"].size(), 1u);  // one per scene, its figures missing without Vulkan
  EXPECT_EQ(j["comparisons"][0]["scene"], "wall");
  EXPECT_TRUE(j["comparisons"][0]["triangles_cpu"].is_null());  // stopped before refine
  EXPECT_TRUE(j["comparisons"][0]["setup_refine_ratio"].is_null());
  EXPECT_NE(r.out.find("! wall on vulkan: unavailable"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Stopped after preprocess"), std::string::npos) << r.out;
  // The same run as Markdown: a table for the CPU backend, Vulkan's reason, the command.
  const std::string md = slurp(markdown);
  const int all = fracref::default_threads();  // the CLI's too: every hardware thread
  const std::string cpu_kind = "CPU backend, " + std::to_string(all) + (all == 1 ? " thread" : " threads");
  EXPECT_EQ(md.rfind("## " + cpu_kind + "; vulkan (unavailable)\n", 0), 0u) << md;
  EXPECT_NE(md.find("`fracref bench --scenes wall --backends cpu,vulkan --repeat 2 --stop-after preprocess --no-kernels`"),
            std::string::npos) << md;
  EXPECT_NE(md.find("### " + cpu_kind + "\n\n| scene | triangles |"), std::string::npos) << md;
  EXPECT_NE(md.find("\n| wall | "), std::string::npos) << md;
  EXPECT_NE(md.find("### vulkan (unavailable)\n\nUnavailable: "), std::string::npos) << md;
}

TEST(CliBench, TheBunnyIsSkippedWithANoteWhenItsMeshIsMissing) {
  TempDir t;
  const auto file = t.path / "bench.json";
  auto r = run("bench --scenes bunny --backends cpu --repeat 1 --no-kernels --json " + file.string(),
               "FRACREF_DATA_DIR=/nonexistent");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(slurp(file));
  EXPECT_EQ(j["stop_after"], "animate");  // the whole pipeline by default
  EXPECT_EQ(j["results"].size(), 0u);
  bool noted = false;
  for (const json& n : j["notes"]) noted |= n.get<std::string>().find("bunny skipped") != std::string::npos;
  EXPECT_TRUE(noted) << j["notes"];
  EXPECT_NE(r.out.find("bunny skipped"), std::string::npos) << r.out;
}

TEST(CliBench, BadOptionsAreRefused) {
  auto r = run("bench --scenes volcano --no-kernels");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("volcano"), std::string::npos) << r.err;
  r = run("bench --backends gpu --no-kernels");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("gpu"), std::string::npos) << r.err;
  r = run("bench --kernels-only --no-kernels");
  EXPECT_EQ(r.code, 2);
  r = run("bench --repeat 0");
  EXPECT_EQ(r.code, 2);
  r = run("bench --kernels-only --kernel-sizes 2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--kernel-sizes"), std::string::npos) << r.err;
}
