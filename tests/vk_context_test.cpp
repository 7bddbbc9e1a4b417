// Device selection (pure, no driver needed), the live context on this machine's driver, the
// validation hook, and resident buffers.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <memory>

#include "util/error.hpp"
#include "vk_buffer.hpp"
#include "vk_context.hpp"
#include "vk_fixture.hpp"

namespace fracref {
namespace {

DeviceCandidate usable(const char* name, VkPhysicalDeviceType type) {
  return {name, type, VK_API_VERSION_1_3, true, true, 1024};
}

std::string selection_error(const std::vector<DeviceCandidate>& candidates) {
  try {
    select_device(candidates, true);
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}

TEST(SelectDevice, RanksDiscreteIntegratedVirtualCpu) {
  std::vector<DeviceCandidate> c = {usable("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                    usable("vm", VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU),
                                    usable("igpu", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
                                    usable("dgpu", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)};
  EXPECT_EQ(select_device(c, true), 3u);
  c.pop_back();
  EXPECT_EQ(select_device(c, true), 2u);
  c.pop_back();
  EXPECT_EQ(select_device(c, true), 1u);
  c.pop_back();
  EXPECT_EQ(select_device(c, true), 0u);
}

TEST(SelectDevice, SkipsUnusableDevicesAndKeepsLoaderOrderWithoutPreference) {
  DeviceCandidate broken = usable("dgpu", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  broken.compute_queue = false;
  const std::vector<DeviceCandidate> c = {broken, usable("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                          usable("igpu", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU)};
  EXPECT_EQ(select_device(c, true), 2u);
  EXPECT_EQ(select_device(c, false), 1u);
}

TEST(SelectDevice, ErrorListsEveryDeviceAndWhy) {
  DeviceCandidate old = usable("old gpu", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  old.api_version = VK_API_VERSION_1_0;
  DeviceCandidate no_compute = usable("display only", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);
  no_compute.compute_queue = false;
  DeviceCandidate no_texel = usable("odd cpu", VK_PHYSICAL_DEVICE_TYPE_CPU);
  no_texel.texel_buffer_formats = false;
  DeviceCandidate narrow = usable("narrow", VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU);
  narrow.max_workgroup_x = 32;
  const std::string msg = selection_error({old, no_compute, no_texel, narrow});
  EXPECT_NE(msg.find("no usable Vulkan device among 4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0] old gpu (discrete GPU): supports Vulkan 1.0.0, fracref needs 1.1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[1] display only (integrated GPU): no queue family supports compute"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[2] odd cpu (CPU): R32_SFLOAT cannot be read as a uniform texel buffer"), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("[3] narrow (virtual GPU): maxComputeWorkGroupSize.x is 32"), std::string::npos) << msg;
}

TEST(SelectDevice, NoDeviceAtAllMeansNoDriver) {
  EXPECT_EQ(selection_error({}), "no Vulkan driver found: install mesa-vulkan-drivers for lavapipe");
}

TEST(VulkanContextDeath, NoDriverIsReportedAsSuch) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // The loader finds no ICD when every driver manifest path points nowhere.
  EXPECT_EXIT(
      {
        setenv("VK_ICD_FILENAMES", "/nonexistent/fracref_icd.json", 1);
        setenv("VK_DRIVER_FILES", "/nonexistent/fracref_icd.json", 1);
        try {
          VulkanContext context;
        } catch (const RunError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(3);
        }
        std::exit(0);
      },
      testing::ExitedWithCode(3), "no Vulkan driver found: install mesa-vulkan-drivers");
}

class LiveContext : public VulkanFixture {};

TEST_F(LiveContext, DescribesTheChosenDevice) {
  const std::string d = context_->describe();
  EXPECT_EQ(d.rfind(context_->properties().deviceName, 0), 0u) << d;
  EXPECT_NE(d.find(device_type_name(context_->properties().deviceType)), std::string::npos) << d;
  EXPECT_NE(d.find("Vulkan 1."), std::string::npos) << d;
  std::printf("device: %s\n", d.c_str());
}

TEST_F(LiveContext, ValidationCallbackRecordsErrors) {
  if (!context_->validation_enabled()) GTEST_SKIP() << "the Khronos validation layer is not installed";
  // Usage 0 is invalid (VUID-VkBufferCreateInfo-usage-requiredbitmask) but harmless to drivers.
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = 64;
  VkBuffer buffer = VK_NULL_HANDLE;
  vkCreateBuffer(context_->device(), &info, nullptr, &buffer);
  if (buffer) vkDestroyBuffer(context_->device(), buffer, nullptr);
  const auto messages = context_->validation_messages();
  ASSERT_FALSE(messages.empty());
  EXPECT_EQ(messages.front().rfind("error: ", 0), 0u) << messages.front();
  context_->clear_validation_messages();
}

TEST_F(LiveContext, BufferGrowsGeometricallyAndKeepsItsContents) {
  VulkanBuffer b(*context_, 100, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  ASSERT_TRUE(b);
  EXPECT_EQ(b.capacity(), 100u);
  for (int i = 0; i < 25; ++i) b.as<int>()[i] = i * 7;
  const VkBuffer before = b.handle();
  EXPECT_FALSE(b.grow(100));
  EXPECT_EQ(b.handle(), before);
  EXPECT_TRUE(b.grow(101));
  EXPECT_EQ(b.capacity(), 150u);
  for (int i = 0; i < 25; ++i) ASSERT_EQ(b.as<int>()[i], i * 7);
  EXPECT_TRUE(b.grow(1000));
  EXPECT_EQ(b.capacity(), 1000u);
  EXPECT_EQ(b.as<int>()[24], 24 * 7);

  VulkanBuffer moved = std::move(b);
  EXPECT_FALSE(b);
  EXPECT_TRUE(moved);
  EXPECT_EQ(moved.capacity(), 1000u);
  EXPECT_EQ(VulkanBuffer(*context_, 0, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT).capacity(), 16u);
}

}  // namespace
}  // namespace fracref
