// The flow kernels' correctly rounded division and square root (shaders/flow_common.h): handed a
// quotient or root a few ulps off, as a device whose own are only faithful gives them (Vulkan
// allows 2.5 ulp for division; an H100 rounds them so), flow_div_from and flow_sqrt_from must
// return exactly what the CPU's IEEE division and sqrtf give. Run through the GLSL itself, on
// whatever device is present (lavapipe in CI), by the test shader tests/shaders/rounding_probe.comp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "spv/rounding_probe_spv.h"
#include "vk_context.hpp"
#include "vk_flow_kernel.hpp"
#include "vk_fixture.hpp"

namespace fracref {
namespace {

constexpr std::uint32_t kGroup = 64;  // the probe's local_size_x

struct Case {
  float a, b, q, s;
};

// `x` moved `steps` ulps up (positive) or down.
float step_ulps(float x, int steps) {
  for (; steps > 0; --steps) x = std::nextafter(x, INFINITY);
  for (; steps < 0; ++steps) x = std::nextafter(x, -INFINITY);
  return x;
}

// A float with `bits` significant bits, a random sign and an exponent in [-20, 20].
float random_float(std::mt19937& rng, int bits) {
  const std::uint32_t mantissa = (rng() >> (32 - bits)) | (1u << (bits - 1));
  const int exponent = int(rng() % 41) - 20 - bits;
  return (rng() & 1 ? -1.0f : 1.0f) * std::ldexp(float(mantissa), exponent);
}

// n cases (a multiple of kGroup): every fourth quotient exact (12-bit b times 12-bit c), the
// others random; q and s are the correctly rounded a/b and sqrt|a| moved by -3..3 ulps.
std::vector<Case> make_cases(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Case> cases(n);
  for (std::size_t i = 0; i < n; ++i) {
    Case& c = cases[i];
    if (i % 4 == 0) {
      c.b = random_float(rng, 12);
      c.a = c.b * random_float(rng, 12);
    } else {
      c.a = random_float(rng, 24);
      c.b = random_float(rng, 24);
    }
    c.q = step_ulps(c.a / c.b, int(rng() % 7) - 3);
    c.s = step_ulps(std::sqrt(std::abs(c.a)), int(rng() % 7) - 3);
  }
  return cases;
}

class VulkanRoundingTest : public VulkanFixture {
 protected:
  // out[k] = (flow_div_from(a, b, q), flow_sqrt_from(|a|, s)) of cases[k], run on the device.
  static std::vector<float> probe(const std::vector<Case>& cases);

};

std::vector<float> VulkanRoundingTest::probe(const std::vector<Case>& cases) {
  VulkanContext& context = *context_;
  DeviceArray in(context, "cases", VK_FORMAT_R32G32B32A32_SFLOAT, 16, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT);
  DeviceArray out(context, "results", VK_FORMAT_UNDEFINED, 8, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  DeviceArray groups(context, "dispatch", VK_FORMAT_UNDEFINED, 12, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
  in.upload(cases.data(), cases.size() * sizeof(Case));
  out.reserve(cases.size());
  const std::uint32_t dispatch[3] = {std::uint32_t(cases.size() / kGroup), 1, 1};
  groups.upload(dispatch, sizeof dispatch);

  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1},
                                        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
  auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 2;
  pool_info.pPoolSizes = sizes;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  vk_check(vkCreateDescriptorPool(context.device(), &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
  {
    FlowKernel kernel(context, rounding_probe_spv, {BindingType::UniformTexelBuffer, BindingType::StorageBuffer},
                      {&in, &out}, pool);
    kernel.refresh();
    auto alloc = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    alloc.commandPool = context.command_pool();
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    vk_check(vkAllocateCommandBuffers(context.device(), &alloc, &cb), "vkAllocateCommandBuffers");
    auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    vk_check(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
    kernel.record_dispatch(cb, groups.handle(), 0);
    flow_barrier(cb, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
    vk_check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
    context.submit_and_wait(cb);
    vkFreeCommandBuffers(context.device(), context.command_pool(), 1, &cb);
  }
  vkDestroyDescriptorPool(context.device(), pool, nullptr);
  std::vector<float> results(2 * cases.size());
  std::memcpy(results.data(), out.data(), results.size() * sizeof(float));
  return results;
}

TEST_F(VulkanRoundingTest, DivisionAndSqrtRoundCorrectlyFromQuotientsAFewUlpsOff) {
  const std::vector<Case> cases = make_cases(256 * kGroup, 7);
  const std::vector<float> out = probe(cases);
  std::size_t moved = 0, bad_div = 0, bad_sqrt = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Case& c = cases[k];
    const float q = c.a / c.b, s = std::sqrt(std::abs(c.a));
    moved += c.q != q;
    // Bit for bit: the kernels' CPU twins divide and take roots in IEEE single precision.
    if (std::memcmp(&out[2 * k], &q, 4) != 0 && bad_div++ < 5) {
      ADD_FAILURE() << c.a << " / " << c.b << " from " << c.q << ": got " << out[2 * k] << ", want " << q;
    }
    if (std::memcmp(&out[2 * k + 1], &s, 4) != 0 && bad_sqrt++ < 5) {
      ADD_FAILURE() << "sqrt " << std::abs(c.a) << " from " << c.s << ": got " << out[2 * k + 1] << ", want " << s;
    }
  }
  EXPECT_GT(moved, cases.size() / 2);  // the cases do start off the correct quotient
  EXPECT_EQ(bad_div, 0u) << "of " << cases.size();
  EXPECT_EQ(bad_sqrt, 0u) << "of " << cases.size();
}

// a / b a hair from a rounding midpoint: with B odd (24 bits) and 2Q + 1 ≡ ∓B⁻¹ (mod 2^25),
// A = (B·(2Q + 1) ± 1) / 2^25 is an integer, and A/B lies 1/(B·2^25) from the midpoint
// (2Q + 1)/2^25, about 2^-25 ulp. Scaled by 2^e.
Case hard_quotient(std::mt19937& rng, int sign) {
  for (;;) {
    const std::uint64_t b = (rng() & 0x7FFFFFu) | 0x800001u;  // odd, 24 bits
    std::uint64_t inv = b;                                    // b⁻¹ mod 2^25 by Newton's iteration
    for (int i = 0; i < 5; ++i) inv = (inv * (2 - b * inv)) & 0x1FFFFFFu;
    const std::uint64_t m = sign > 0 ? (0x2000000u - inv) & 0x1FFFFFFu : inv;  // 2Q + 1
    if (m < 0x1000000u) continue;                                              // Q in [2^23, 2^24)
    const std::uint64_t num = b * m + (sign > 0 ? 1 : 0) - (sign > 0 ? 0 : 1);
    if (num % 0x2000000u != 0) continue;
    const std::uint64_t a = num / 0x2000000u;
    if (a < 0x800000u || a >= 0x1000000u) continue;
    const int e = int(rng() % 21) - 10;
    const float af = std::ldexp(float(a), e), bf = float(b);
    return {af, bf, af / bf, std::sqrt(af)};
  }
}

// Quotients and roots a hair from a rounding midpoint, where the residual's one rounding can land
// on the wrong side: the quotients above, and the roots of the floats just below and above each
// power of four (2^-27 and 2^-26 ulp from one). Squared areas of faces on a dyadic lattice hit
// those: the bunny's Vulkan run once differed from its CPU run by such a root. Each case starts
// from the correct result or an ulp either side.
TEST_F(VulkanRoundingTest, QuotientsAndRootsAHairFromAMidpointRoundCorrectly) {
  std::mt19937 rng(11);
  std::vector<Case> cases;
  for (int i = 0; i < 4 * int(kGroup); ++i) {
    Case c = hard_quotient(rng, i % 2 ? 1 : -1);
    c.q = step_ulps(c.q, i % 3 - 1);
    cases.push_back(c);
  }
  for (int e = -60; e <= 60; e += 2)
    for (const float x : {std::nextafter(std::ldexp(1.0f, e), 0.0f), std::nextafter(std::ldexp(1.0f, e), INFINITY)})
      for (int off = -1; off <= 1; ++off) cases.push_back({x, 1.0f, x, step_ulps(std::sqrt(x), off)});
  while (cases.size() % kGroup) cases.push_back(cases.back());
  const std::vector<float> out = probe(cases);
  std::size_t bad_div = 0, bad_sqrt = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Case& c = cases[k];
    const float q = c.a / c.b, s = std::sqrt(std::abs(c.a));
    if (std::memcmp(&out[2 * k], &q, 4) != 0 && bad_div++ < 5)
      ADD_FAILURE() << c.a << " / " << c.b << " from " << c.q << ": got " << out[2 * k] << ", want " << q;
    if (std::memcmp(&out[2 * k + 1], &s, 4) != 0 && bad_sqrt++ < 5)
      ADD_FAILURE() << "sqrt " << std::abs(c.a) << " from " << c.s << ": got " << out[2 * k + 1] << ", want " << s;
  }
  EXPECT_EQ(bad_div, 0u) << "of " << cases.size();
  EXPECT_EQ(bad_sqrt, 0u) << "of " << cases.size();
}

TEST_F(VulkanRoundingTest, ZeroAndNonFiniteQuotientsPassThrough) {
  std::vector<Case> cases(kGroup, Case{1.0f, 3.0f, 1.0f / 3.0f, 1.0f});
  cases[0] = {0.0f, 2.0f, 0.0f, 0.0f};
  cases[1] = {1.0f, 0.0f, INFINITY, 1.0f};
  cases[2] = {0.0f, 0.0f, NAN, 0.0f};
  const std::vector<float> out = probe(cases);
  EXPECT_EQ(out[0], 0.0f);
  EXPECT_EQ(out[1], 0.0f);  // sqrt 0
  EXPECT_EQ(out[2], INFINITY);
  EXPECT_TRUE(std::isnan(out[4]));
  EXPECT_EQ(out[6], 1.0f / 3.0f);
  EXPECT_EQ(out[7], 1.0f);
}

}  // namespace
}  // namespace fracref
