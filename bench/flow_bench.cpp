// The flow kernels, CPU backend (1 and 2 threads) against the Vulkan backend on the chosen
// device: K1 + K2 (vertex_velocities) and K3 (sample_tests, one sample per triangle at its
// centroid with the triangle's three edges as fan) on a wavy grid surface of 10K, 100K and 1M
// vertices in Morton order, sampling a 64³ FieldGrid4; plus the fixed costs of the Vulkan path
// (an empty submit + wait; a whole call on 9 vertices). Each timed call includes what a
// real call does: uploads, the topology comparison, the copy back. Wall-clock time. Run with
// --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true and compare medians
// (the machine's speed drifts).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <random>

#include "flow/backend.hpp"
#include "vk_backend.hpp"

namespace fracref {
namespace {

struct Scene {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
  std::vector<std::uint32_t> vf_offsets, vf_faces;
  std::vector<glm::vec4> points;  // K3: one sample per face
  std::vector<std::uint32_t> fan_offsets;
  std::vector<glm::uvec2> fan_pairs;
  SurfaceView view() const { return {positions, faces, vf_offsets, vf_faces}; }
  SampleView samples() const { return {points, fan_offsets, fan_pairs}; }
};

std::uint64_t spread3(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

std::uint64_t morton(glm::vec3 p) {  // p in [-1.5, 1.5]³
  const glm::uvec3 q = glm::uvec3(glm::clamp((p + 1.5f) / 3.0f, 0.0f, 1.0f) * float((1 << 21) - 1));
  return spread3(q.x) | spread3(q.y) << 1 | spread3(q.z) << 2;
}

template <class T>
std::vector<std::uint32_t> morton_order(const std::vector<T>& items, auto&& position) {
  std::vector<std::uint64_t> code(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) code[i] = morton(position(items[i]));
  std::vector<std::uint32_t> order(items.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
  return order;
}

// A side x side grid on z = 0.2 sin(3x) cos(2y) over [-1, 1]², split along alternating diagonals,
// vertices and faces renumbered in Morton order, with its vertex→faces CSR and K3's samples.
Scene make_scene(unsigned vertices) {
  const unsigned side = unsigned(std::lround(std::sqrt(double(vertices))));
  std::vector<glm::vec4> grid;
  for (unsigned y = 0; y < side; ++y)
    for (unsigned x = 0; x < side; ++x) {
      const float u = 2.0f * x / (side - 1) - 1.0f, v = 2.0f * y / (side - 1) - 1.0f;
      grid.push_back({u, v, 0.2f * std::sin(3.0f * u) * std::cos(2.0f * v), 1.0f});
    }
  const std::vector<std::uint32_t> order = morton_order(grid, [](const glm::vec4& p) { return glm::vec3(p); });
  std::vector<std::uint32_t> rank(order.size());
  Scene s;
  for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i, s.positions.push_back(grid[order[i]]);
  std::vector<glm::uvec4> faces;
  for (unsigned y = 0; y + 1 < side; ++y)
    for (unsigned x = 0; x + 1 < side; ++x) {
      const unsigned a = rank[x + side * y], b = rank[x + 1 + side * y], c = rank[x + side * (y + 1)],
                     d = rank[x + 1 + side * (y + 1)];
      if ((x + y) % 2) faces.push_back({a, b, d, 0}), faces.push_back({a, d, c, 0});
      else faces.push_back({a, b, c, 0}), faces.push_back({b, d, c, 0});
    }
  auto centroid = [&](const glm::uvec4& f) {
    return glm::vec3(s.positions[f.x] + s.positions[f.y] + s.positions[f.z]) / 3.0f;
  };
  for (std::uint32_t j : morton_order(faces, centroid)) s.faces.push_back(faces[j]);
  s.vf_offsets.assign(s.positions.size() + 1, 0);
  for (const auto& f : s.faces)
    for (int k = 0; k < 3; ++k) ++s.vf_offsets[f[k] + 1];
  std::partial_sum(s.vf_offsets.begin(), s.vf_offsets.end(), s.vf_offsets.begin());
  s.vf_faces.resize(s.vf_offsets.back());
  std::vector<std::uint32_t> fill(s.vf_offsets.begin(), s.vf_offsets.end() - 1);
  for (std::uint32_t j = 0; j < s.faces.size(); ++j)
    for (int k = 0; k < 3; ++k) s.vf_faces[fill[s.faces[j][k]]++] = j;
  s.fan_offsets.push_back(0);
  for (const glm::uvec4& f : s.faces) {
    s.points.push_back(glm::vec4(centroid(f), 1.0f));
    for (glm::uvec2 p : {glm::uvec2(f.x, f.y), glm::uvec2(f.y, f.z), glm::uvec2(f.z, f.x)}) s.fan_pairs.push_back(p);
    s.fan_offsets.push_back(std::uint32_t(s.fan_pairs.size()));
  }
  return s;
}

const Scene& scene(unsigned vertices) {
  static std::map<unsigned, Scene> cache;
  auto it = cache.find(vertices);
  if (it == cache.end()) it = cache.emplace(vertices, make_scene(vertices)).first;
  return it->second;
}

const FieldGrid4& field() {
  static const FieldGrid4 f = [] {
    FieldGrid4 g;
    g.dims = {64, 64, 64};
    g.origin = glm::dvec3(-1.1);
    g.cell = 2.2 / 63.0;
    g.values.resize(64 * 64 * 64);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (glm::vec4& v : g.values) v = {u(rng), u(rng), u(rng), u(rng)};
    return g;
  }();
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
  const Scene& s = scene(unsigned(state.range(0)));
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
  const Scene& s = scene(unsigned(state.range(0)));
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
  const Scene& s = scene(9);
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
