// The bench's backend comparison: each non-cpu result against the same scene on cpu.
#include <algorithm>
#include <cmath>

#include "harness/bench.hpp"

namespace fracref {
namespace {

const SceneBenchResult* cpu_of(const std::vector<SceneBenchResult>& all, const std::string& scene) {
  for (const SceneBenchResult& c : all)
    if (c.scene == scene && c.backend == "cpu") return &c;
  return nullptr;
}

std::optional<double> median_or_none(const std::vector<double>& v) {
  return v.empty() ? std::nullopt : std::optional<double>(median(v));
}

/// (other - cpu) / |cpu|; 0 when both are 0, nullopt when only cpu is.
std::optional<double> relative(double other, double cpu) {
  if (cpu == 0.0) return other == 0.0 ? std::optional<double>(0.0) : std::nullopt;
  return (other - cpu) / std::fabs(cpu);
}

/// Each run's setup + refine + the backend's start-up; empty when refine never ran.
std::vector<double> setup_refine(const SceneBenchResult& r) {
  std::vector<double> out;
  for (std::size_t i = 0; i < std::min(r.setup.size(), r.refine.size()); ++i)
    out.push_back(r.setup[i] + r.refine[i] + r.startup_seconds);
  return out;
}

void compare_triangles(const SceneBenchResult& cpu, const SceneBenchResult& other, SceneComparison& c) {
  c.triangles_cpu = cpu.refined_triangles;
  c.triangles_other = other.refined_triangles;
  if (!c.triangles_cpu || !c.triangles_other) return;
  c.triangle_difference = std::int64_t(*c.triangles_other) - std::int64_t(*c.triangles_cpu);
  c.triangle_relative_difference = relative(double(*c.triangles_other), double(*c.triangles_cpu));
}

void compare_times(const SceneBenchResult& cpu, const SceneBenchResult& other, SceneComparison& c) {
  const std::vector<double> a = setup_refine(other), b = setup_refine(cpu);
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (b[i] > 0.0) c.setup_refine_ratios.push_back(a[i] / b[i]);
  c.setup_refine_ratio = median_or_none(c.setup_refine_ratios);
  if (!other.total.empty() && !cpu.total.empty() && median(cpu.total) > 0.0)
    c.total_ratio = median(other.total) / median(cpu.total);
}

}  // namespace

std::vector<SceneComparison> compare_backends(const std::vector<SceneBenchResult>& results) {
  std::vector<SceneComparison> out;
  for (const SceneBenchResult& r : results) {
    const SceneBenchResult* cpu = r.backend == "cpu" ? nullptr : cpu_of(results, r.scene);
    if (!cpu) continue;
    SceneComparison c;
    c.scene = r.scene;
    c.backend = r.backend;
    compare_triangles(*cpu, r, c);
    c.energy_cpu = median_or_none(cpu->final_energy);
    c.energy_other = median_or_none(r.final_energy);
    if (c.energy_cpu && c.energy_other) c.energy_relative_difference = relative(*c.energy_other, *c.energy_cpu);
    compare_times(*cpu, r, c);
    out.push_back(c);
  }
  return out;
}

}  // namespace fracref
