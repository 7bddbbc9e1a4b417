// Gaussian pyramid (5 levels, sigma 1): CPU twin (1 and 2 threads) against VulkanPyramid on
// the chosen device, on 50³ (the bunny scene's grid) and 128³ grids. Wall-clock time: lavapipe
// and the CPU twin both run on worker threads. Run with --benchmark_repetitions=5
// --benchmark_enable_random_interleaving=true (the machine's speed drifts; compare medians).
#include <benchmark/benchmark.h>

#include <memory>
#include <random>

#include "field/pyramid.hpp"
#include "vk_pyramid.hpp"

namespace fracref {
namespace {

Grid3 random_grid(unsigned n) {
  Grid3 g;
  g.dims = {n, n, n};
  g.values.resize(g.size());
  std::mt19937 rng(n);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& v : g.values) v = u(rng);
  return g;
}

void BM_PyramidCpu(benchmark::State& state) {
  const Grid3 base = random_grid(unsigned(state.range(0)));
  const PyramidOptions options{.levels = 5, .threads = int(state.range(1))};
  for (auto _ : state) benchmark::DoNotOptimize(build_pyramid_cpu(base, options));
  state.SetItemsProcessed(state.iterations() * std::int64_t(base.size()));
}
BENCHMARK(BM_PyramidCpu)->ArgNames({"n", "threads"})->ArgsProduct({{50, 128}, {1, 2}})->UseRealTime()
    ->Unit(benchmark::kMillisecond);

VulkanContext* context() {
  static std::unique_ptr<VulkanContext> ctx = [] {
    std::string why;
    return vulkan_available(&why) ? std::make_unique<VulkanContext>() : nullptr;
  }();
  return ctx.get();
}

void BM_PyramidVulkan(benchmark::State& state) {
  std::string why;
  if (!vulkan_available(&why) || !context()) {
    state.SkipWithError(("no Vulkan: " + why).c_str());
    return;
  }
  const Grid3 base = random_grid(unsigned(state.range(0)));
  VulkanPyramid pyramid(*context(), {.levels = 5});
  pyramid.build(base);  // records, and lets the driver compile the pipeline, outside the timing
  for (auto _ : state) benchmark::DoNotOptimize(pyramid.build(base));
  state.SetItemsProcessed(state.iterations() * std::int64_t(base.size()));
  state.SetLabel(context()->describe());
}
BENCHMARK(BM_PyramidVulkan)->ArgNames({"n"})->Arg(50)->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fracref

BENCHMARK_MAIN();
