// The Vulkan pyramid against its CPU twin, under the validation layer (synchronization
// validation included): same levels, replayable, re-recorded only when the shape changes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "field/pyramid.hpp"
#include "util/error.hpp"
#include "vk_pyramid.hpp"
#include "vk_fixture.hpp"

namespace fracref {
namespace {

Grid3 random_grid(glm::uvec3 dims, unsigned seed) {
  Grid3 g;
  g.dims = dims;
  g.origin = glm::dvec3(0.5, -2.0, 1.25);
  g.cell = 0.02;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f);
  g.values.resize(g.size());
  for (float& v : g.values) v = u(rng);
  return g;
}

// |a-b| <= 1e-5 * max(1, |a|) at every node of every level, and the same geometry.
void expect_same_pyramid(const std::vector<Grid3>& cpu, const std::vector<Grid3>& gpu) {
  ASSERT_EQ(cpu.size(), gpu.size());
  for (std::size_t l = 0; l < cpu.size(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    ASSERT_EQ(cpu[l].dims, gpu[l].dims);
    EXPECT_EQ(cpu[l].origin, gpu[l].origin);
    EXPECT_EQ(cpu[l].cell, gpu[l].cell);
    ASSERT_EQ(gpu[l].values.size(), cpu[l].size());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < cpu[l].values.size(); ++i) {
      const float a = cpu[l].values[i], b = gpu[l].values[i];
      if (!(std::abs(a - b) <= 1e-5f * std::max(1.0f, std::abs(a))) && bad++ < 5) {
        ADD_FAILURE() << "node " << i << ": cpu " << a << " vulkan " << b;
      }
    }
    EXPECT_EQ(bad, 0u);
  }
}

bool bit_identical(const std::vector<Grid3>& a, const std::vector<Grid3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t l = 0; l < a.size(); ++l) {
    if (a[l].values.size() != b[l].values.size() ||
        std::memcmp(a[l].values.data(), b[l].values.data(), a[l].values.size() * sizeof(float)) != 0) {
      return false;
    }
  }
  return true;
}

class VulkanPyramidTest : public VulkanFixture {};

TEST_F(VulkanPyramidTest, ValidationLayerIsActive) {
  if (!context_->validation_enabled()) GTEST_SKIP() << "the Khronos validation layer is not installed";
  SUCCEED() << context_->describe();
}

TEST_F(VulkanPyramidTest, MatchesCpuOnOddAndEvenGridsForEveryLevelCount) {
  for (glm::uvec3 dims : {glm::uvec3(17, 9, 5), glm::uvec3(32, 32, 32), glm::uvec3(50, 50, 50)}) {
    const Grid3 base = random_grid(dims, dims.x * 31 + dims.z);
    VulkanPyramid gpu(*context_);
    for (int levels = 1; levels <= 6; ++levels) {
      SCOPED_TRACE(std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) +
                   ", levels " + std::to_string(levels));
      const PyramidOptions options{.levels = levels};
      gpu.set_options(options);
      expect_same_pyramid(build_pyramid_cpu(base, options), gpu.build(base));
    }
  }
}

TEST_F(VulkanPyramidTest, MatchesCpuForOtherSigmasAndTinyGrids) {
  VulkanPyramid gpu(*context_);
  for (float sigma : {0.3f, 0.5f, 1.7f, 3.0f}) {
    for (glm::uvec3 dims : {glm::uvec3(1, 1, 1), glm::uvec3(2, 7, 1), glm::uvec3(40, 3, 12)}) {
      SCOPED_TRACE("sigma " + std::to_string(sigma) + ", dims " + std::to_string(dims.x) + "x" +
                   std::to_string(dims.y) + "x" + std::to_string(dims.z));
      const PyramidOptions options{.levels = 8, .sigma = sigma};
      gpu.set_options(options);
      const Grid3 base = random_grid(dims, 5);
      expect_same_pyramid(build_pyramid_cpu(base, options), gpu.build(base));
    }
  }
}

TEST_F(VulkanPyramidTest, ReplaysWithoutRecordingAgain) {
  VulkanPyramid gpu(*context_, {.levels = 5});
  const Grid3 a = random_grid({33, 20, 18}, 1), b = random_grid({33, 20, 18}, 2);
  const auto first = gpu.build(a);
  const auto second = gpu.build(a);
  EXPECT_TRUE(bit_identical(first, second));
  EXPECT_EQ(gpu.record_count(), 1u);
  // New values, same dims: the recorded commands are replayed on the new input.
  expect_same_pyramid(build_pyramid_cpu(b, {.levels = 5}), gpu.build(b));
  EXPECT_EQ(gpu.record_count(), 1u);
  EXPECT_TRUE(bit_identical(first, gpu.build(a)));
}

TEST_F(VulkanPyramidTest, ReRecordsWhenDimsOrOptionsChange) {
  VulkanPyramid gpu(*context_, {.levels = 4});
  const Grid3 small = random_grid({10, 12, 14}, 3), large = random_grid({40, 36, 30}, 4);
  gpu.build(small);
  EXPECT_EQ(gpu.record_count(), 1u);
  expect_same_pyramid(build_pyramid_cpu(large, {.levels = 4}), gpu.build(large));  // buffers grow
  EXPECT_EQ(gpu.record_count(), 2u);
  expect_same_pyramid(build_pyramid_cpu(small, {.levels = 4}), gpu.build(small));  // and are reused
  EXPECT_EQ(gpu.record_count(), 3u);
  gpu.set_options({.levels = 4, .threads = 1});  // threads do not matter to the GPU
  gpu.build(small);
  EXPECT_EQ(gpu.record_count(), 3u);
  gpu.set_options({.levels = 4, .sigma = 2.0f});
  expect_same_pyramid(build_pyramid_cpu(small, {.levels = 4, .sigma = 2.0f}), gpu.build(small));
  EXPECT_EQ(gpu.record_count(), 4u);
  gpu.prepare(large.dims);
  EXPECT_EQ(gpu.record_count(), 5u);
  gpu.build(large);
  EXPECT_EQ(gpu.record_count(), 5u);
}

TEST_F(VulkanPyramidTest, LevelsStayResidentForLaterKernels) {
  VulkanPyramid gpu(*context_, {.levels = 4});
  EXPECT_THROW(gpu.level_buffer(0), RunError);
  const Grid3 base = random_grid({21, 16, 11}, 8);
  const auto levels = gpu.build(base);
  for (int l = 0; l < 4; ++l) {
    const VulkanBuffer& buffer = gpu.level_buffer(l);
    ASSERT_GE(buffer.capacity(), levels[l].values.size() * sizeof(float));
    EXPECT_EQ(0, std::memcmp(buffer.data(), levels[l].values.data(), levels[l].values.size() * sizeof(float)));
  }
  EXPECT_THROW(gpu.level_buffer(4), RunError);
  gpu.prepare({5, 5, 5});  // another shape: the buffers no longer hold this pyramid
  EXPECT_THROW(gpu.level_buffer(0), RunError);
}

TEST_F(VulkanPyramidTest, RejectsWhatTheCpuRejects) {
  EXPECT_THROW(VulkanPyramid(*context_, {.levels = 9}), InputError);
  VulkanPyramid gpu(*context_);
  EXPECT_THROW(gpu.set_options({.sigma = -1.0f}), InputError);
  Grid3 bad = random_grid({4, 4, 4}, 1);
  bad.values.pop_back();
  EXPECT_THROW(gpu.build(bad), InputError);
  EXPECT_THROW(gpu.prepare({4, 0, 4}), InputError);
  EXPECT_EQ(gpu.record_count(), 0u);
}

TEST_F(VulkanPyramidTest, GridsBeyondTheDeviceLimitsSayWhatToDo) {
  VulkanPyramid gpu(*context_);
  const glm::uvec3 tall(1, 1, context_->limits().maxComputeWorkGroupCount[1] + 1);
  try {
    gpu.prepare(tall);
    FAIL() << "no error for a base of " << tall.z << " planes";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("use the CPU backend"), std::string::npos) << e.what();
  }
  EXPECT_EQ(gpu.record_count(), 0u);
  expect_same_pyramid(build_pyramid_cpu(random_grid({6, 5, 4}, 2), {}), gpu.build(random_grid({6, 5, 4}, 2)));
}

}  // namespace
}  // namespace fracref
