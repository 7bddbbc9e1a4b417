// The Vulkan backend against the CPU backend, under the validation layer (synchronization
// validation included): K1 + K2 and K3 on random meshes, fields and samples, replays after
// position-only changes, growth between size classes, and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "flow/backend.hpp"
#include "util/error.hpp"
#include "vk_backend.hpp"
#include "vk_fixture.hpp"

namespace fracref {
namespace {

struct Mesh {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
  std::vector<std::uint32_t> vf_offsets, vf_faces;

  void build_csr() {
    vf_offsets.assign(positions.size() + 1, 0);
    for (const auto& f : faces)
      for (int k = 0; k < 3; ++k) ++vf_offsets[f[k] + 1];
    for (std::size_t i = 0; i < positions.size(); ++i) vf_offsets[i + 1] += vf_offsets[i];
    vf_faces.assign(vf_offsets.back(), 0);
    std::vector<std::uint32_t> fill(vf_offsets.begin(), vf_offsets.end() - 1);
    for (std::uint32_t j = 0; j < faces.size(); ++j)
      for (int k = 0; k < 3; ++k) vf_faces[fill[faces[j][k]]++] = j;
  }
  SurfaceView view() const { return {positions, faces, vf_offsets, vf_faces}; }
};

// A jittered nx x ny grid with random heights, random diagonals and about one face in five
// flipped (the formula takes each face in its own orientation).
Mesh grid_mesh(unsigned nx, unsigned ny, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f), height(-0.4f, 0.4f), coin(0.0f, 1.0f);
  Mesh m;
  const float h = 2.0f / float(std::max(nx, ny));
  for (unsigned y = 0; y < ny; ++y)
    for (unsigned x = 0; x < nx; ++x)
      m.positions.push_back({(x + jitter(rng)) * h - 1.0f, (y + jitter(rng)) * h - 1.0f, height(rng) * h, 1.0f});
  for (unsigned y = 0; y + 1 < ny; ++y)
    for (unsigned x = 0; x + 1 < nx; ++x) {
      const unsigned a = x + nx * y, b = a + 1, c = a + nx, d = c + 1;
      glm::uvec4 t[2] = {{a, b, d, 0}, {a, d, c, 0}};
      if (coin(rng) < 0.5f) t[0] = {a, b, c, 0}, t[1] = {b, d, c, 0};
      for (glm::uvec4 f : t) m.faces.push_back(coin(rng) < 0.2f ? glm::uvec4(f.x, f.z, f.y, 0) : f);
    }
  m.build_csr();
  return m;
}

// A UV sphere of radius ~0.9 with 2 + rings * segments vertices and a noisy radius; the poles
// have `segments` incident faces and the faces next to them are slivers.
Mesh sphere_mesh(unsigned rings, unsigned segments, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
  Mesh m;
  auto push = [&](float theta, float phi) {
    const float r = 0.9f + noise(rng);
    m.positions.push_back({r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                           r * std::cos(theta), 1.0f});
  };
  push(0.0f, 0.0f);
  for (unsigned i = 1; i <= rings; ++i)
    for (unsigned j = 0; j < segments; ++j) push(float(M_PI) * i / (rings + 1), 2.0f * float(M_PI) * j / segments);
  push(float(M_PI), 0.0f);
  const unsigned south = 1 + rings * segments;
  auto ring = [&](unsigned i, unsigned j) { return 1 + (i - 1) * segments + j % segments; };
  for (unsigned j = 0; j < segments; ++j) {
    m.faces.push_back({0u, ring(1, j), ring(1, j + 1), 0u});
    m.faces.push_back({south, ring(rings, j + 1), ring(rings, j), 0u});
    for (unsigned i = 1; i < rings; ++i) {
      m.faces.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), 0u});
      m.faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1), 0u});
    }
  }
  m.build_csr();
  return m;
}

// A horizontal 5 x 5 sheet and a vertical 5 x 3 sheet standing on its middle row (the junction
// edges have three faces), a zero-area face and an isolated vertex.
Mesh t_junction() {
  Mesh m;
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) m.positions.push_back({0.3f * x - 0.6f, 0.3f * y - 0.6f, 0.01f * (x * y % 3), 1.0f});
  std::vector<unsigned> id(15);
  for (int z = 0; z < 3; ++z)
    for (int x = 0; x < 5; ++x) {
      if (z == 0) {
        id[x] = 10 + x;  // the middle row of the horizontal sheet
        continue;
      }
      id[x + 5 * z] = unsigned(m.positions.size());
      m.positions.push_back({0.3f * x - 0.6f, 0.02f * z, 0.3f * z, 1.0f});
    }
  for (unsigned y = 0; y < 4; ++y)
    for (unsigned x = 0; x < 4; ++x) {
      const unsigned a = x + 5 * y;
      m.faces.push_back({a, a + 1, a + 6, 0u});
      m.faces.push_back({a, a + 6, a + 5, 0u});
    }
  for (unsigned z = 0; z < 2; ++z)
    for (unsigned x = 0; x < 4; ++x) {
      const unsigned a = id[x + 5 * z], b = id[x + 1 + 5 * z], c = id[x + 5 * (z + 1)], d = id[x + 1 + 5 * (z + 1)];
      m.faces.push_back({a, b, d, 0u});
      m.faces.push_back({a, d, c, 0u});
    }
  const unsigned e = unsigned(m.positions.size());
  m.positions.push_back(glm::mix(m.positions[0], m.positions[24], 0.25f));  // on the line 0-24
  m.positions.push_back({2.0f, 2.0f, 2.0f, 1.0f});                         // isolated
  m.faces.push_back({0u, e, 24u, 0u});
  m.build_csr();
  return m;
}

// Random (ψ, ∇ψ) on a small grid whose box covers only part of [-1, 1]³ (clamping is exercised).
FieldGrid4 random_field(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  FieldGrid4 f;
  f.dims = {7 + seed % 3, 9, 6};
  f.origin = glm::dvec3(-0.8, -0.9, -0.7);
  f.cell = 0.23;
  f.values.resize(std::size_t(f.dims.x) * f.dims.y * f.dims.z);
  for (glm::vec4& v : f.values) v = {u(rng), u(rng), u(rng), u(rng)};
  return f;
}

struct Samples {
  std::vector<glm::vec4> points;
  std::vector<std::uint32_t> fan_offsets{0};
  std::vector<glm::uvec2> fan_pairs;
  SampleView view() const { return {points, fan_offsets, fan_pairs}; }
};

// A point inside each of `count` random faces with the face's three edges as its fan, and as
// many random points with 0..6 random vertex pairs (the first of them with an empty fan).
Samples random_samples(const Mesh& m, std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), box(-1.1f, 1.1f);
  std::uniform_int_distribution<std::size_t> face(0, m.faces.size() - 1), vertex(0, m.positions.size() - 1);
  Samples s;
  for (std::size_t k = 0; k < count; ++k) {
    const glm::uvec4 f = m.faces[face(rng)];
    float a = u(rng), b = u(rng) * (1.0f - a);
    s.points.push_back(a * m.positions[f.x] + b * m.positions[f.y] + (1.0f - a - b) * m.positions[f.z]);
    for (glm::uvec2 p : {glm::uvec2(f.x, f.y), glm::uvec2(f.y, f.z), glm::uvec2(f.z, f.x)}) s.fan_pairs.push_back(p);
    s.fan_offsets.push_back(std::uint32_t(s.fan_pairs.size()));
  }
  for (std::size_t k = 0; k < count; ++k) {
    s.points.push_back({box(rng), box(rng), box(rng), 1.0f});
    const std::size_t pairs = k == 0 ? 0 : k % 7;
    for (std::size_t q = 0; q < pairs; ++q) s.fan_pairs.push_back(glm::uvec2(vertex(rng), vertex(rng)));
    s.fan_offsets.push_back(std::uint32_t(s.fan_pairs.size()));
  }
  return s;
}

// The larger of |a − b| / max(1, |a|) for the vector part xyz and for w.
float difference(const glm::vec4& a, const glm::vec4& b) {
  const float dv = glm::length(glm::vec3(a) - glm::vec3(b)), dw = std::abs(a.w - b.w);
  return std::max(dv / std::max(1.0f, glm::length(glm::vec3(a))), dw / std::max(1.0f, std::abs(a.w)));
}

// For samples (ψ, ∇ψ): ψ is the scalar, ∇ψ the vector.
float sample_difference(const glm::vec4& a, const glm::vec4& b) {
  return difference(glm::vec4(a.y, a.z, a.w, a.x), glm::vec4(b.y, b.z, b.w, b.x));
}

// Every value within 1e-5 (relative, as `difference` measures); a failure says how many were
// not and the largest difference, so a device's rounding can be read off one run.
void expect_close(const std::vector<glm::vec4>& cpu, const std::vector<glm::vec4>& gpu, const char* what,
                  float (*diff)(const glm::vec4&, const glm::vec4&) = difference) {
  ASSERT_EQ(cpu.size(), gpu.size());
  std::size_t bad = 0, worst = 0;
  float largest = 0.0f;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const float d = diff(cpu[i], gpu[i]);
    if (d > largest) largest = d, worst = i;
    if (d <= 1e-5f) continue;
    if (bad++ < 5) {
      const glm::vec4 a = cpu[i], b = gpu[i];
      ADD_FAILURE() << what << "[" << i << "]: cpu (" << a.x << ", " << a.y << ", " << a.z << ", " << a.w
                    << ") vulkan (" << b.x << ", " << b.y << ", " << b.z << ", " << b.w << ")";
    }
  }
  EXPECT_EQ(bad, 0u) << what << ": " << bad << " of " << cpu.size() << " values beyond 1e-5, the largest difference "
                     << largest << " at " << worst;
}

class VulkanBackendTest : public VulkanFixture {
 protected:
  // K1 + K2 on both backends: the outputs agree; returns the CPU samples for K3.
  static std::vector<glm::vec4> compare_vertices(ComputeBackend& cpu, ComputeBackend& gpu, const Mesh& m) {
    const std::size_t n = m.positions.size();
    std::vector<glm::vec4> s_cpu(n), v_cpu(n), s_gpu(n, glm::vec4(7.0f)), v_gpu(n, glm::vec4(7.0f));
    cpu.vertex_velocities(m.view(), s_cpu, v_cpu);
    gpu.vertex_velocities(m.view(), s_gpu, v_gpu);
    expect_close(s_cpu, s_gpu, "samples", sample_difference);
    expect_close(v_cpu, v_gpu, "velocity");
    return s_cpu;
  }
  static void compare_samples(ComputeBackend& cpu, ComputeBackend& gpu, const Mesh& m,
                              const std::vector<glm::vec4>& vertex_samples, const Samples& s) {
    std::vector<glm::vec4> o_cpu(s.points.size()), o_gpu(s.points.size(), glm::vec4(7.0f));
    cpu.sample_tests(m.positions, vertex_samples, s.view(), o_cpu);
    gpu.sample_tests(m.positions, vertex_samples, s.view(), o_gpu);
    expect_close(o_cpu, o_gpu, "sample test");
  }

};

TEST_F(VulkanBackendTest, ValidationLayerIsActive) {
  if (!context_->validation_enabled()) GTEST_SKIP() << "the Khronos validation layer is not installed";
  SUCCEED() << context_->describe();
}

TEST_F(VulkanBackendTest, NameSaysVulkanAndTheDevice) {
  auto gpu = make_vulkan_backend(*context_);
  EXPECT_EQ(gpu->name(), std::string("vulkan (") + context_->properties().deviceName + ")");
}

TEST_F(VulkanBackendTest, MatchesCpuOnGridsAndSpheresOfEverySize) {
  struct Case {
    const char* name;
    Mesh mesh;
  };
  const Case cases[] = {{"grid 10", grid_mesh(5, 2, 1)},        {"sphere 10", sphere_mesh(2, 4, 2)},
                        {"grid 1000", grid_mesh(40, 25, 3)},    {"sphere 990", sphere_mesh(26, 38, 4)},
                        {"grid 50000", grid_mesh(250, 200, 5)}, {"sphere 50002", sphere_mesh(200, 250, 6)}};
  auto cpu = make_cpu_backend(2);
  auto gpu = make_vulkan_backend(*context_);
  unsigned seed = 10;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const FieldGrid4 field = random_field(seed++);
    cpu->set_field(field);
    gpu->set_field(field);
    const std::vector<glm::vec4> samples = compare_vertices(*cpu, *gpu, c.mesh);
    compare_samples(*cpu, *gpu, c.mesh, samples, random_samples(c.mesh, std::min<std::size_t>(c.mesh.faces.size(), 3000), seed++));
  }
}

TEST_F(VulkanBackendTest, MatchesCpuAtANonManifoldTJunction) {
  const Mesh m = t_junction();
  ASSERT_EQ(m.vf_offsets[12] - m.vf_offsets[11], 9u);  // a junction vertex: 6 + 3 faces
  const FieldGrid4 field = random_field(3);
  auto cpu = make_cpu_backend(1);
  auto gpu = make_vulkan_backend(*context_);
  cpu->set_field(field);
  gpu->set_field(field);
  const std::size_t n = m.positions.size();
  std::vector<glm::vec4> s(n), v(n);
  gpu->vertex_velocities(m.view(), s, v);
  EXPECT_EQ(v[n - 1], glm::vec4(0.0f));  // the isolated vertex
  const std::vector<glm::vec4> samples = compare_vertices(*cpu, *gpu, m);
  compare_samples(*cpu, *gpu, m, samples, random_samples(m, 40, 8));
}

// The kernels repeat the CPU's arithmetic exactly on any device that honours `precise` (which
// Vulkan requires) and rounds +, −, × correctly: division and sqrt are rounded correctly in the
// shader (vk_rounding_test). Any drift in operation order shows here before it shows in 1e-5.
// Seen bit-identical on lavapipe and on an NVIDIA H100 (whose own division and sqrt are faithful).
TEST_F(VulkanBackendTest, BitIdenticalToCpu) {
  SCOPED_TRACE(context_->describe());
  const Mesh m = sphere_mesh(60, 80, 21);
  const FieldGrid4 field = random_field(8);
  auto cpu = make_cpu_backend(2);
  auto gpu = make_vulkan_backend(*context_);
  cpu->set_field(field);
  gpu->set_field(field);
  const std::size_t n = m.positions.size();
  std::vector<glm::vec4> s_cpu(n), v_cpu(n), s_gpu(n), v_gpu(n);
  cpu->vertex_velocities(m.view(), s_cpu, v_cpu);
  gpu->vertex_velocities(m.view(), s_gpu, v_gpu);
  EXPECT_EQ(std::memcmp(s_cpu.data(), s_gpu.data(), n * sizeof(glm::vec4)), 0);
  EXPECT_EQ(std::memcmp(v_cpu.data(), v_gpu.data(), n * sizeof(glm::vec4)), 0);
  const Samples samples = random_samples(m, 2000, 22);
  std::vector<glm::vec4> o_cpu(samples.points.size()), o_gpu(samples.points.size());
  cpu->sample_tests(m.positions, s_cpu, samples.view(), o_cpu);
  gpu->sample_tests(m.positions, s_cpu, samples.view(), o_gpu);
  EXPECT_EQ(std::memcmp(o_cpu.data(), o_gpu.data(), o_cpu.size() * sizeof(glm::vec4)), 0);
}

TEST_F(VulkanBackendTest, ReplaysWhenOnlyPositionsChange) {
  Mesh m = sphere_mesh(30, 40, 11);
  const FieldGrid4 field = random_field(4);
  auto cpu = make_cpu_backend(2);
  VulkanBackend gpu(*context_);
  cpu->set_field(field);
  gpu.set_field(field);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> step(-0.01f, 0.01f);
  for (int round = 0; round < 4; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const std::vector<glm::vec4> samples = compare_vertices(*cpu, gpu, m);
    compare_samples(*cpu, gpu, m, samples, random_samples(m, 500, 20 + round));
    for (glm::vec4& p : m.positions) p += glm::vec4(step(rng), step(rng), step(rng), 0.0f);
  }
  EXPECT_EQ(gpu.stats().topology_uploads, 1u);
  EXPECT_EQ(gpu.stats().records, 2u);  // K1 + K2 once, K3 once
  EXPECT_EQ(gpu.stats().submits, 8u);
}

TEST_F(VulkanBackendTest, UploadsTopologyWhenItsContentChanges) {
  Mesh m = grid_mesh(20, 20, 12);
  const FieldGrid4 field = random_field(5);
  auto cpu = make_cpu_backend(1);
  VulkanBackend gpu(*context_);
  cpu->set_field(field);
  gpu.set_field(field);
  compare_vertices(*cpu, gpu, m);
  std::swap(m.faces[7].y, m.faces[7].z);  // same sizes, other orientation
  compare_vertices(*cpu, gpu, m);
  EXPECT_EQ(gpu.stats().topology_uploads, 2u);
  compare_vertices(*cpu, gpu, m);
  EXPECT_EQ(gpu.stats().topology_uploads, 2u);
  EXPECT_EQ(gpu.stats().records, 1u);
}

TEST_F(VulkanBackendTest, GrowsFromASmallToALargeMeshAndBack) {
  const Mesh small = grid_mesh(4, 3, 13), medium = sphere_mesh(20, 30, 14), large = grid_mesh(220, 200, 15);
  const FieldGrid4 field = random_field(6);
  auto cpu = make_cpu_backend(2);
  VulkanBackend gpu(*context_);
  cpu->set_field(field);
  gpu.set_field(field);
  std::size_t records = 0;
  for (const Mesh* m : {&small, &medium, &large}) {
    const std::vector<glm::vec4> samples = compare_vertices(*cpu, gpu, *m);
    compare_samples(*cpu, gpu, *m, samples, random_samples(*m, m->faces.size() / 2, 30));
    EXPECT_GT(gpu.stats().records, records);  // larger size classes: recorded again
    records = gpu.stats().records;
  }
  const std::vector<glm::vec4> samples = compare_vertices(*cpu, gpu, small);  // buffers stay large
  compare_samples(*cpu, gpu, small, samples, random_samples(small, 5, 31));
  EXPECT_EQ(gpu.stats().records, records);
}

TEST_F(VulkanBackendTest, RefusesMissingFieldBadSizesAndBadIndices) {
  VulkanBackend gpu(*context_);
  Mesh m = grid_mesh(6, 6, 16);
  std::vector<glm::vec4> s(m.positions.size()), v(m.positions.size());
  EXPECT_THROW(gpu.vertex_velocities(m.view(), s, v), RunError);  // no field yet
  FieldGrid4 bad = random_field(7);
  bad.values.pop_back();
  EXPECT_THROW(gpu.set_field(bad), RunError);
  const FieldGrid4 field = random_field(7);
  gpu.set_field(field);
  std::vector<glm::vec4> short_out(3);
  EXPECT_THROW(gpu.vertex_velocities(m.view(), short_out, v), RunError);
  Mesh broken = m;
  broken.faces[4].z = std::uint32_t(m.positions.size());
  EXPECT_THROW(gpu.vertex_velocities(broken.view(), s, v), RunError);
  EXPECT_THROW(gpu.vertex_velocities(broken.view(), s, v), RunError);  // checked again, not cached
  Samples fans = random_samples(m, 4, 1);
  fans.fan_pairs[2].x = 1000;
  std::vector<glm::vec4> out(fans.points.size());
  EXPECT_THROW(gpu.sample_tests(m.positions, s, fans.view(), out), RunError);
  // And it still works afterwards.
  auto cpu = make_cpu_backend(1);
  cpu->set_field(field);
  const std::vector<glm::vec4> samples = compare_vertices(*cpu, gpu, m);
  compare_samples(*cpu, gpu, m, samples, random_samples(m, 10, 2));
}

TEST_F(VulkanBackendTest, BuildsThePyramidLikeTheCpu) {
  Grid3 base;
  base.dims = {12, 9, 7};
  base.values.resize(base.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& x : base.values) x = u(rng);
  auto gpu = make_vulkan_backend(*context_);
  const PyramidOptions options{.levels = 3};
  const std::vector<Grid3> a = build_pyramid_cpu(base, options), b = gpu->build_pyramid(base, options);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t l = 0; l < a.size(); ++l) {
    ASSERT_EQ(a[l].values.size(), b[l].values.size());
    for (std::size_t i = 0; i < a[l].values.size(); ++i)
      EXPECT_NEAR(a[l].values[i], b[l].values[i], 1e-5f * std::max(1.0f, std::abs(a[l].values[i])));
  }
}

TEST(VulkanBackendOwning, CreatesItsOwnContextOrSaysWhyNot) {
  std::string why;
  if (!vulkan_available(&why)) {
    try {
      make_vulkan_backend();
      ADD_FAILURE() << "expected RunError";
    } catch (const RunError& e) {
      EXPECT_NE(std::string(e.what()).find("vulkan backend: "), std::string::npos) << e.what();
    }
    return;
  }
  auto gpu = make_vulkan_backend();
  EXPECT_EQ(gpu->name().rfind("vulkan (", 0), 0u);
}

}  // namespace
}  // namespace fracref
