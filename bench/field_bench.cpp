// Procedural strength fields (field/procedural.hpp): sample_strength on a 64³ grid, one thread,
// per material. Run with --benchmark_repetitions=5 (compare medians).
#include <benchmark/benchmark.h>

#include "field/procedural.hpp"

namespace fracref {
namespace {

void BM_SampleStrength64(benchmark::State& state) {
  const std::string type = field_type_names()[std::size_t(state.range(0))];
  FieldSpec spec;
  spec.type = type;
  spec.object_min = {-1, -1, -1};
  spec.object_max = {1, 1, 1};
  for (auto _ : state) benchmark::DoNotOptimize(sample_strength(spec, spec.object_min, spec.object_max, {64, 64, 64}, 1));
  state.SetItemsProcessed(state.iterations() * 64 * 64 * 64);
  state.SetLabel(type);
}
BENCHMARK(BM_SampleStrength64)->DenseRange(0, int(field_type_names().size()) - 1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fracref

BENCHMARK_MAIN();
