// The one view-march skeleton (core/march/sample_march.h) against exact
// limits: the slab entry's geometry, and on a homogeneous slab the sample
// count, the transmittance (1 - alpha)^n and the weights the callbacks see.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/march/sample_march.h"

namespace clothbake {
namespace {
using Imath::V3f;

/// A homogeneous slab: 4 x 4 x 4 cells over 1 x 1 x 0.5 mm, density `rho`.
VolumeTexture slab(float rho) {
  VolumeTexture v(4, 4, 4, V3f(1.0f, 1.0f, 0.5f));
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) v.at(i, j, k).density = rho;
  return v;
}

TEST(SlabEntry, FrontBehindAndAlongTheFaces) {
  const VolumeTexture v = slab(1.0f);
  const V3f top(0.3f, 0.6f, 0.5f);
  // Straight down from the top face: the whole thickness.
  SlabEntry e = slab_entry(v, top, V3f(0, 0, -1));
  EXPECT_EQ(e.entry_texture, top);
  EXPECT_FLOAT_EQ(e.length_mm, 0.5f);
  // From behind at 60 degrees from the normal: thickness / cos, from the
  // bottom face below the hit along the ray.
  const V3f d = V3f(std::sin(1.0471976f), 0.0f, std::cos(1.0471976f));
  e = slab_entry(v, top, d);
  EXPECT_NEAR(e.length_mm, 0.5f / std::cos(1.0471976f), 1e-5f);
  EXPECT_EQ(e.entry_texture.z, 0.0f);
  EXPECT_NEAR(e.entry_texture.x, top.x - d.x * e.length_mm, 1e-5f);
  // Along the faces: nothing to march.
  EXPECT_EQ(slab_entry(v, top, V3f(1, 0, 0)).length_mm, 0.0f);
}

// Straight down through a homogeneous slab with step s and jitter j: samples
// at (j + i) s for (j + i) s < thickness; each has opacity
// alpha = 1 - exp(-sigma rho s) and weight T_i alpha with T_i = (1 - alpha)^i.
TEST(SampleMarch, HomogeneousSlabExactSumsAndWeights) {
  const float rho = 0.5f, sigma = 10.0f, step = 0.01f, jitter = 0.25f;
  const VolumeTexture v = slab(rho);
  SampleMarchInput in;
  in.volume = &v;
  in.entry_texture = V3f(0.3f, 0.6f, 0.5f);
  in.dir_texture = V3f(0, 0, -1);
  in.length_mm = 0.5f;
  in.extinction_per_mm = sigma;
  in.step_mm = step;
  in.jitter = jitter;
  in.cutoff = 0.0f;
  in.roulette = 0.0f;
  int cells = 0;
  std::vector<float> weights;
  const SampleMarchResult r = march_samples(
      in, [&](const Cell&, int) { ++cells; },
      [&](const V3f& p, float w) {
        EXPECT_NEAR(p.z, 0.5f - (jitter + float(weights.size())) * step, 1e-4f);
        weights.push_back(w);
      });
  const int n = int(std::ceil(0.5f / step - jitter));  // samples with t < 0.5
  EXPECT_EQ(r.samples, n);
  EXPECT_EQ(int(weights.size()), n);
  EXPECT_EQ(cells, 4);  // every layer holds samples
  const double alpha = 1.0 - std::exp(-double(sigma) * rho * step);
  EXPECT_NEAR(r.transmittance, std::pow(1.0 - alpha, n), 1e-5);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(weights[size_t(i)], std::pow(1.0 - alpha, i) * alpha, 1e-5);
}

// The cutoff stops the march at the first sample whose transmittance falls
// below it and reports 0; the roulette keeps the expected weight: over many
// seeds the mean weight of a sample behind the threshold is T alpha.
TEST(SampleMarch, CutoffAndRouletteKeepTheExpectation) {
  const VolumeTexture v = slab(4.0f);
  SampleMarchInput in;
  in.volume = &v;
  in.entry_texture = V3f(0.3f, 0.6f, 0.5f);
  in.dir_texture = V3f(0, 0, -1);
  in.length_mm = 0.5f;
  in.extinction_per_mm = 10.0f;
  in.step_mm = 0.01f;
  in.jitter = 0.0f;
  in.cutoff = 0.05f;
  const double alpha = 1.0 - std::exp(-10.0 * 4.0 * 0.01);
  const int stop = int(std::ceil(std::log(0.05) / std::log(1.0 - alpha)));  // T_stop < cutoff
  const SampleMarchResult r = march_samples(in, [](const Cell&, int) {}, [](const V3f&, float) {});
  EXPECT_EQ(r.samples, stop);
  EXPECT_EQ(r.transmittance, 0.0f);

  in.cutoff = 0.0f;
  in.length_mm = 0.2f;  // 20 samples; T falls below 0.5 after 3
  in.roulette = 0.5f;
  const int seeds = 20000;
  std::vector<double> mean(20, 0.0);
  for (int s = 0; s < seeds; ++s) {
    in.seed = uint64_t(s) * 0x9e3779b97f4a7c15ull + 1;
    int i = 0;
    march_samples(in, [](const Cell&, int) {}, [&](const V3f& p, float w) {
      i = int(std::lround((0.5f - p.z) / 0.01f));
      mean[size_t(i)] += w;
    });
  }
  for (int i = 0; i < 20; ++i) {
    const double t = std::pow(1.0 - alpha, i), expect = t * alpha;
    const double p = std::min(1.0, t / 0.5);
    // Bernoulli(p) times expect / p: standard error expect sqrt((1 - p) / p / seeds).
    const double se = expect * std::sqrt((1.0 - p) / p / seeds);
    EXPECT_NEAR(mean[size_t(i)] / seeds, expect, 5.0 * se + 1e-7) << "sample " << i;
  }
}

}  // namespace
}  // namespace clothbake
