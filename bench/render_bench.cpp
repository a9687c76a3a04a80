// The reference renderer on the paper scene: wall time at default settings,
// march samples per second per core, and the speed ratios the project
// promises (cached light transmittance against the per-sample shadow march;
// the fibre table against the direct ellipsoid), each with the error it buys.
#include <cmath>
#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "core/render/renderer.h"
#include "io/scene_json.h"

namespace {

using namespace clothbake;

const Scene& paper_scene() {
  static const Scene scene = io::load_scene(CLOTHBAKE_SOURCE_DIR "/testscenes/paper/scene.json");
  return scene;
}

// Relative RMSE over RGB (RMSE / mean of the reference).
double relative_rmse(const Image& ref, const Image& img) {
  double se = 0.0, mean = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    if (i % 4 == 3) continue;
    se += (ref.pixels[i] - img.pixels[i]) * (ref.pixels[i] - img.pixels[i]);
    mean += ref.pixels[i];
    ++n;
  }
  return std::sqrt(se / n) / (mean / n);
}

std::map<std::string, Image>& images() {
  static std::map<std::string, Image> m;
  return m;
}

void run(benchmark::State& state, const std::string& name, Scene scene, int threads,
         const char* compare_to) {
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
  Image image;
  double total = 0.0;
  uint64_t samples = 0;
  double render_only = 0.0;
  for (auto _ : state) {
    Renderer r(scene, uint64_t(8) << 30);
    image = r.render();
    total += r.stats().setup_seconds + r.stats().render_seconds;
    render_only += r.stats().render_seconds;
    samples += r.stats().march_samples;
  }
  images()[name] = image;
  state.counters["seconds"] = total / state.iterations();
  state.counters["march_samples_per_s_per_core"] = double(samples) / render_only / threads;
  if (compare_to && images().count(compare_to)) {
    const Image& ref = images()[compare_to];
    state.counters["rel_rmse_vs_" + std::string(compare_to)] = relative_rmse(ref, image);
  }
}

// Whole paper scene at its default settings on both cores.
void BM_PaperScene(benchmark::State& state) { run(state, "paper", paper_scene(), 2, nullptr); }
BENCHMARK(BM_PaperScene)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

// One core: march samples per second per core.
void BM_PaperSceneOneCore(benchmark::State& state) {
  run(state, "paper_1core", paper_scene(), 1, nullptr);
}
BENCHMARK(BM_PaperSceneOneCore)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

Scene half_res(Scene s) {
  s.camera.width /= 2;
  s.camera.height /= 2;
  return s;
}

// Ratios at half resolution (213 x 133), same seed: the images differ only by
// the method, so rel_rmse is that method's error, not noise. The scene's own
// settings (table, shadow march) are the baseline.
void BM_ShadowMarch(benchmark::State& state) {
  Scene s = half_res(paper_scene());
  s.settings.transmittance = TransmittanceMode::ShadowMarch;
  run(state, "shadow", s, 2, nullptr);
}
BENCHMARK(BM_ShadowMarch)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// The light roulette (the default, 0.25) against every sample's lights: the
// same seed, so rel_rmse is the noise the roulette adds.
void BM_NoLightRoulette(benchmark::State& state) {
  Scene s = half_res(paper_scene());
  s.settings.transmittance = TransmittanceMode::ShadowMarch;
  s.settings.light_roulette = 0.0f;
  run(state, "no_roulette", s, 2, "shadow");
}
BENCHMARK(BM_NoLightRoulette)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

void BM_Cached(benchmark::State& state) {
  Scene s = half_res(paper_scene());
  s.settings.transmittance = TransmittanceMode::Cached;
  run(state, "cached", s, 2, "shadow");
}
BENCHMARK(BM_Cached)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

void BM_Ellipsoid(benchmark::State& state) {
  Scene s = half_res(paper_scene());
  s.settings.fiber_model = FiberModelKind::Ellipsoid;
  run(state, "ellipsoid", s, 2, "shadow");
}
BENCHMARK(BM_Ellipsoid)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_KajiyaKay(benchmark::State& state) {
  Scene s = half_res(paper_scene());
  s.settings.fiber_model = FiberModelKind::KajiyaKay;
  run(state, "kajiya_kay", s, 2, "ellipsoid");
}
BENCHMARK(BM_KajiyaKay)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_TableAgainstEllipsoid(benchmark::State& state) {
  run(state, "table", half_res(paper_scene()), 2, "ellipsoid");
}
BENCHMARK(BM_TableAgainstEllipsoid)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
