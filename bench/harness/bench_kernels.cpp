// The kernel half of `fracref bench`: pyramid, K1+K2, K3 and the fixed cost per call, on a
// Morton-ordered synthetic surface, through the ComputeBackend interface.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "harness/bench.hpp"
#include "geom/morton.hpp"

namespace fracref {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t morton(glm::vec3 p) {  // p in [-1.5, 1.5]³
  const glm::uvec3 q = glm::uvec3(glm::clamp((p + 1.5f) / 3.0f, 0.0f, 1.0f) * float((1 << 21) - 1));
  return morton_interleave(q.x, q.y, q.z);
}

/// The permutation sorting `points` by Morton code on the fixed cube above (ties by index:
/// deterministic). Not geom's morton_order, which fits the grid to the points' bounds: the bench
/// surfaces keep one order whatever their extent.
std::vector<std::uint32_t> morton_order(const std::vector<glm::vec3>& points) {
  std::vector<std::uint64_t> code(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) code[i] = morton(points[i]);
  std::vector<std::uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
  return order;
}

void build_csr_and_samples(BenchSurface& s) {
  s.vf_offsets.assign(s.positions.size() + 1, 0);
  for (const auto& f : s.faces)
    for (int k = 0; k < 3; ++k) ++s.vf_offsets[f[k] + 1];
  std::partial_sum(s.vf_offsets.begin(), s.vf_offsets.end(), s.vf_offsets.begin());
  s.vf_faces.resize(s.vf_offsets.back());
  std::vector<std::uint32_t> fill(s.vf_offsets.begin(), s.vf_offsets.end() - 1);
  for (std::uint32_t j = 0; j < s.faces.size(); ++j)
    for (int k = 0; k < 3; ++k) s.vf_faces[fill[s.faces[j][k]]++] = j;
  s.fan_offsets.assign(1, 0);
  for (const glm::uvec4& f : s.faces) {
    s.points.push_back((s.positions[f.x] + s.positions[f.y] + s.positions[f.z]) / 3.0f);
    s.points.back().w = 1.0f;
    for (glm::uvec2 p : {glm::uvec2(f.x, f.y), glm::uvec2(f.y, f.z), glm::uvec2(f.z, f.x)}) s.fan_pairs.push_back(p);
    s.fan_offsets.push_back(std::uint32_t(s.fan_pairs.size()));
  }
}

Grid3 bench_grid() {
  Grid3 g;
  g.dims = {64, 64, 64};
  g.values.resize(g.size());
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& v : g.values) v = u(rng);
  return g;
}

/// Buffers of one backend for one surface, and the call each kernel makes.
struct KernelCase {
  const BenchSurface* surface = nullptr;
  std::vector<glm::vec4> samples, velocity, out;
  void resize() {
    samples.resize(surface->positions.size());
    velocity.resize(surface->positions.size());
    out.resize(surface->points.size());
  }
};

void call(const std::string& kernel, ComputeBackend& be, KernelCase& c, const Grid3& grid) {
  if (kernel == "pyramid") {
    volatile std::size_t keep = be.build_pyramid(grid, PyramidOptions{}).size();
    (void)keep;
  } else if (kernel == "k1k2" || kernel == "call_k1k2") {
    be.vertex_velocities(c.surface->view(), c.samples, c.velocity);
  } else {
    be.sample_tests(c.surface->positions, c.samples, c.surface->samples(), c.out);
  }
}

/// One sample: an untimed call (uploads, recording, compilation), then `calls` timed calls.
/// On the first sample (calls == 0) `calls` is chosen so that a sample lasts min_seconds.
double sample_ms(const std::string& kernel, ComputeBackend& be, KernelCase& c, const Grid3& grid, int& calls,
                 double min_seconds) {
  if (kernel == "k3" || kernel == "call_k3") be.vertex_velocities(c.surface->view(), c.samples, c.velocity);
  auto t = Clock::now();
  call(kernel, be, c, grid);
  if (calls == 0) {
    const double first = std::chrono::duration<double>(Clock::now() - t).count();
    calls = int(std::clamp(std::ceil(min_seconds / std::max(first, 1e-7)), 1.0, 10000.0));
  }
  t = Clock::now();
  for (int i = 0; i < calls; ++i) call(kernel, be, c, grid);
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count() / calls;
}

/// Runs `kernels` at one size, interleaved, appending one result per (kernel, backend).
void bench_size(const std::vector<std::string>& kernels, std::size_t size, const BenchSurface* surface,
                const std::vector<BenchBackend>& backends, const KernelBenchOptions& o, const Grid3& grid,
                std::vector<KernelBenchResult>& results, std::size_t& done, std::size_t total) {
  const std::size_t first = results.size();
  std::vector<KernelCase> cases(backends.size());
  for (const std::string& k : kernels)
    for (std::size_t b = 0; b < backends.size(); ++b) {
      results.push_back({k, size, backends[b].key, {}, 0, ""});
      if (!backends[b].backend) results.back().error = "unavailable: " + backends[b].unavailable;
    }
  for (KernelCase& c : cases) c.surface = surface;
  if (surface)
    for (KernelCase& c : cases) c.resize();
  for (int rep = 0; rep < o.repeat; ++rep)
    for (std::size_t k = 0; k < kernels.size(); ++k)
      for (std::size_t b = 0; b < backends.size(); ++b, ++done) {
        KernelBenchResult& r = results[first + k * backends.size() + b];
        if (!r.error.empty()) continue;
        if (o.progress) o.progress(kernels[k] + " " + std::to_string(size) + " " + r.backend, double(done) / total);
        try {
          r.ms.push_back(sample_ms(kernels[k], *backends[b].backend, cases[b], grid, r.calls_per_sample,
                                   o.min_sample_seconds));
        } catch (const std::exception& e) {
          r.error = e.what();
        }
      }
}

}  // namespace

FieldGrid4 make_bench_field() {
  FieldGrid4 g;
  g.dims = {64, 64, 64};
  g.origin = glm::dvec3(-1.1);
  g.cell = 2.2 / 63.0;
  g.values.resize(std::size_t(64) * 64 * 64);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (glm::vec4& v : g.values) v = {u(rng), u(rng), u(rng), u(rng)};
  return g;
}

BenchSurface make_bench_surface(std::size_t vertices) {
  const unsigned side = std::max(2u, unsigned(std::lround(std::sqrt(double(vertices)))));
  std::vector<glm::vec3> grid;
  for (unsigned y = 0; y < side; ++y)
    for (unsigned x = 0; x < side; ++x) {
      const float u = 2.0f * float(x) / float(side - 1) - 1.0f, v = 2.0f * float(y) / float(side - 1) - 1.0f;
      grid.push_back({u, v, 0.2f * std::sin(3.0f * u) * std::cos(2.0f * v)});
    }
  BenchSurface s;
  const std::vector<std::uint32_t> order = morton_order(grid);
  std::vector<std::uint32_t> rank(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i, s.positions.push_back(glm::vec4(grid[order[i]], 1.0f));
  std::vector<glm::uvec4> faces;
  std::vector<glm::vec3> centroids;
  for (unsigned y = 0; y + 1 < side; ++y)
    for (unsigned x = 0; x + 1 < side; ++x) {
      const unsigned a = rank[x + side * y], b = rank[x + 1 + side * y], c = rank[x + side * (y + 1)],
                     d = rank[x + 1 + side * (y + 1)];
      if ((x + y) % 2) faces.push_back({a, b, d, 0}), faces.push_back({a, d, c, 0});
      else faces.push_back({a, b, c, 0}), faces.push_back({b, d, c, 0});
    }
  for (const glm::uvec4& f : faces)
    centroids.push_back(glm::vec3(s.positions[f.x] + s.positions[f.y] + s.positions[f.z]) / 3.0f);
  for (std::uint32_t j : morton_order(centroids)) s.faces.push_back(faces[j]);
  build_csr_and_samples(s);
  return s;
}

std::vector<KernelBenchResult> bench_kernels(const std::vector<BenchBackend>& backends, const KernelBenchOptions& o) {
  const FieldGrid4 field = make_bench_field();
  const Grid3 grid = bench_grid();
  for (const BenchBackend& b : backends)
    if (b.backend) b.backend->set_field(field);
  const std::size_t per_rep = backends.size() * (3 + 2 * o.sizes.size());
  const std::size_t total = std::max<std::size_t>(1, per_rep * std::size_t(o.repeat));
  std::vector<KernelBenchResult> results;
  std::size_t done = 0;
  bench_size({"pyramid"}, grid.size(), nullptr, backends, o, grid, results, done, total);
  const BenchSurface tiny = make_bench_surface(9);
  bench_size({"call_k1k2", "call_k3"}, tiny.positions.size(), &tiny, backends, o, grid, results, done, total);
  for (std::size_t size : o.sizes) {
    const BenchSurface surface = make_bench_surface(size);
    bench_size({"k1k2", "k3"}, surface.positions.size(), &surface, backends, o, grid, results, done, total);
  }
  if (o.progress) o.progress("kernels done", 1.0);
  return results;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace fracref
