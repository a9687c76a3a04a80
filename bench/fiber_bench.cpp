// Speed of the fibre models (baker/core/fiber/fiber_model.h, fiber_table.h): one item
// is one evaluation of (tangent, L, E). Inputs are random but fixed directions.

#include <cmath>
#include <numbers>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/fiber/fiber_model.h"
#include "core/fiber/fiber_table.h"
#include "core/util/random.h"

namespace {

using clothbake::FiberResponse;
using Imath::V3f;

struct Config {
  V3f tangent, light, eye;
};

/// 1024 fixed configurations with directions uniform on the sphere.
const std::vector<Config>& configs() {
  static const std::vector<Config> all = [] {
    std::vector<Config> v(1024);
    clothbake::Rng rng(clothbake::hash_key(0xbe7c4));
    auto direction = [&] {
      const double z = 2.0 * rng.next_double() - 1.0;
      const double phi = 2.0 * std::numbers::pi * rng.next_double();
      const double r = std::sqrt(1.0 - z * z);
      return V3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    };
    for (Config& c : v) c = {direction(), direction(), direction()};
    return v;
  }();
  return all;
}

const clothbake::FiberTable& table() {
  static const clothbake::FiberTable t = clothbake::FiberTable::build({});
  return t;
}

void BM_Ellipsoid(benchmark::State& state) {
  clothbake::EllipsoidFiberParams params;
  params.samples = static_cast<int>(state.range(0));
  const std::vector<Config>& c = configs();
  size_t i = 0;
  for (auto _ : state) {
    const Config& k = c[i++ & 1023];
    benchmark::DoNotOptimize(clothbake::ellipsoid_fiber(k.tangent, k.light, k.eye, params, i));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Ellipsoid)->Arg(16)->Arg(64)->Arg(256);

void BM_TableLookup(benchmark::State& state) {
  const clothbake::FiberTable& t = table();
  const std::vector<Config>& c = configs();
  size_t i = 0;
  for (auto _ : state) {
    const Config& k = c[i++ & 1023];
    benchmark::DoNotOptimize(t.eval(k.tangent, k.light, k.eye));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_TableLookup);

void BM_KajiyaKay(benchmark::State& state) {
  const std::vector<Config>& c = configs();
  size_t i = 0;
  for (auto _ : state) {
    const Config& k = c[i++ & 1023];
    benchmark::DoNotOptimize(clothbake::kajiya_kay_fiber(k.tangent, k.light, k.eye, 20.0f));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_KajiyaKay);

/// Default table (25 x 48 x 48 entries, 64 samples each), all threads; items = entries.
void BM_TableBuild(benchmark::State& state) {
  size_t entries = 0;
  for (auto _ : state) {
    const clothbake::FiberTable t = clothbake::FiberTable::build({});
    entries = t.entry_count();
    benchmark::DoNotOptimize(t.diffuse_entries().data());
  }
  state.SetItemsProcessed(int64_t(state.iterations() * entries));
}
BENCHMARK(BM_TableBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
