#pragma once
// The fixture of the vk_ tests: one VulkanContext (validation on) per test suite, the suite's
// tests skipped with the reason when no Vulkan driver is usable, and every test required to
// leave the validation layer silent.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "vk_context.hpp"

namespace fracref {

class VulkanFixture : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string why;
    if (vulkan_available(&why)) context_ = std::make_unique<VulkanContext>(VulkanContextOptions{.validation = true});
    else skip_reason_ = why;
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override {
    if (!context_) GTEST_SKIP() << "no Vulkan: " << skip_reason_;
    context_->clear_validation_messages();
  }
  void TearDown() override {
    if (!context_) return;
    const auto messages = context_->validation_messages();
    EXPECT_EQ(messages.size(), 0u);
    for (std::size_t i = 0; i < messages.size() && i < 5; ++i) ADD_FAILURE() << messages[i];
  }

  static inline std::unique_ptr<VulkanContext> context_;
  static inline std::string skip_reason_;
};

}  // namespace fracref
