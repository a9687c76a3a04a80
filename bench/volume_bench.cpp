// Volume generation: time and memory for grids up to 256 x 256 x 32.
#include <benchmark/benchmark.h>

#include "core/texture/volume_generator.h"

namespace {

void BM_GenerateVolume(benchmark::State& state) {
  clothbake::ClothSpec spec;
  spec.resolution.cells_x = spec.resolution.cells_y = int(state.range(0));
  spec.resolution.layers = int(state.range(1));
  spec.resolution.supersample = int(state.range(2));
  for (auto _ : state) {
    auto volume = clothbake::generate_volume(spec, uint64_t(16) << 30);
    benchmark::DoNotOptimize(volume.cells().data());
  }
  const double cells = double(state.range(0)) * state.range(0) * state.range(1);
  state.SetItemsProcessed(int64_t(state.iterations() * cells));
  state.counters["cells"] = cells;
  state.counters["grid_MiB"] = double(clothbake::estimated_volume_bytes(spec)) / (1 << 20);
}
BENCHMARK(BM_GenerateVolume)
    ->Args({64, 16, 2})
    ->Args({256, 32, 1})
    ->Args({256, 32, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
