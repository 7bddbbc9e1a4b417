// The flow kernels, CPU backend (1 and 2 threads) against the Vulkan backend on the chosen
// device: K1 + K2 (vertex_velocities) and K3 (sample_tests, one sample per triangle at its
// centroid with the triangle's three edges as fan) on `fracref bench`'s synthetic surfaces
// (make_bench_surface: a wavy grid of 10K, 100K and 1M vertices in Morton order) sampling its
// 64³ FieldGrid4 (make_bench_field); plus the fixed costs of the Vulkan path
// (an empty submit + wait; a whole call on 9 vertices). Each timed call includes what a
// real call does: uploads, the topology comparison, the copy back. Wall-clock time. Run with
// --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true and compare medians
// (the machine's speed drifts).
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "harness/bench.hpp"
#include "flow/backend.hpp"
#include "vk_backend.hpp"

namespace fracref {
namespace {

const BenchSurface& surface(unsigned vertices) {
  static std::map<unsigned, BenchSurface> cache;
  auto it = cache.find(vertices);
  if (it == cache.end()) it = cache.emplace(vertices, make_bench_surface(vertices)).first;
  return it->second;
}

const FieldGrid4& field() {
  static const FieldGrid4 f = make_bench_field();
  return f;
}

VulkanContext* context(std::string* why) {
  static std::string reason;
  static std::unique_ptr<VulkanContext> ctx = [] {
    return vulkan_available(&reason) ? std::make_unique<VulkanContext>() : nullptr;
  }();
  *why = reason;
  return ctx.get();
}

// backend: 1 or 2 = CPU with that many threads, 0 = Vulkan (nullptr and a skip when none).
std::unique_ptr<ComputeBackend> backend(benchmark::State& state, int which) {
  if (which > 0) return make_cpu_backend(which);
  std::string why;
  VulkanContext* ctx = context(&why);
  if (!ctx) {
    state.SkipWithError(("no Vulkan: " + why).c_str());
    return nullptr;
  }
  state.SetLabel(ctx->describe());
  return make_vulkan_backend(*ctx);
}

void BM_VertexVelocities(benchmark::State& state) {
  const BenchSurface& s = surface(unsigned(state.range(0)));
  auto be = backend(state, int(state.range(1)));
  if (!be) return;
  be->set_field(field());
  std::vector<glm::vec4> samples(s.positions.size()), velocity(s.positions.size());
  be->vertex_velocities(s.view(), samples, velocity);  // uploads, records, compiles: untimed
  for (auto _ : state) {
    be->vertex_velocities(s.view(), samples, velocity);
    benchmark::DoNotOptimize(velocity.data());
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(s.positions.size()));
}

void BM_SampleTests(benchmark::State& state) {
  const BenchSurface& s = surface(unsigned(state.range(0)));
  auto be = backend(state, int(state.range(1)));
  if (!be) return;
  be->set_field(field());
  std::vector<glm::vec4> samples(s.positions.size()), velocity(s.positions.size()), out(s.points.size());
  be->vertex_velocities(s.view(), samples, velocity);
  be->sample_tests(s.positions, samples, s.samples(), out);
  for (auto _ : state) {
    be->sample_tests(s.positions, samples, s.samples(), out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(s.points.size()));
}

const std::vector<std::vector<std::int64_t>> kSizes = {{10'000, 100'000, 1'000'000}, {1, 2, 0}};
BENCHMARK(BM_VertexVelocities)->ArgNames({"vertices", "threads_or_vk"})->ArgsProduct(kSizes)->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SampleTests)->ArgNames({"vertices", "threads_or_vk"})->ArgsProduct(kSizes)->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The floor under every Vulkan call: one submit of an empty command buffer and the fence wait.
void BM_VulkanEmptySubmit(benchmark::State& state) {
  std::string why;
  VulkanContext* ctx = context(&why);
  if (!ctx) return state.SkipWithError(("no Vulkan: " + why).c_str());
  auto alloc = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = ctx->command_pool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  vk_check(vkAllocateCommandBuffers(ctx->device(), &alloc, &cb), "vkAllocateCommandBuffers");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  vk_check(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
  vk_check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
  for (auto _ : state) ctx->submit_and_wait(cb);
  vkFreeCommandBuffers(ctx->device(), ctx->command_pool(), 1, &cb);
  state.SetLabel(ctx->describe());
}
BENCHMARK(BM_VulkanEmptySubmit)->UseRealTime()->Unit(benchmark::kMicrosecond);

// The fixed cost of one backend call: K1 + K2 replayed on a 3 x 3 grid (9 vertices).
void BM_TinyVertexVelocities(benchmark::State& state) {
  const BenchSurface& s = surface(9);
  auto be = backend(state, int(state.range(0)));
  if (!be) return;
  be->set_field(field());
  std::vector<glm::vec4> samples(s.positions.size()), velocity(s.positions.size());
  be->vertex_velocities(s.view(), samples, velocity);
  for (auto _ : state) be->vertex_velocities(s.view(), samples, velocity);
}
BENCHMARK(BM_TinyVertexVelocities)->ArgNames({"threads_or_vk"})->Arg(1)->Arg(0)->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace fracref

BENCHMARK_MAIN();
