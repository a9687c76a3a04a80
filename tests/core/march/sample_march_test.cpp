// The one view-march skeleton (core/march/sample_march.h) against exact
// limits: the slab entry's geometry; on a homogeneous slab the cells'
// opacities, the samples' strata and the weights the callbacks see; and on
// an opaque slab lit from above, the expected radiance against the closed
// form, where equally spaced samples were ten times too dark.

#include <algorithm>
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

SampleMarchInput straight_down(const VolumeTexture& v, float sigma, float step) {
  SampleMarchInput in;
  in.volume = &v;
  in.entry_texture = V3f(0.3f, 0.6f, 0.5f);
  in.dir_texture = V3f(0, 0, -1);
  in.length_mm = 0.5f;
  in.extinction_per_mm = sigma;
  in.step_mm = step;
  in.cutoff = 0.0f;
  in.roulette = 0.0f;
  return in;
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

// Straight down through a homogeneous slab (4 layers of 0.125 mm) with step
// s: each layer holds round(0.125 / s) samples of equal weight
// T_layer alpha / n, alpha = 1 - exp(-sigma rho 0.125), one in each stratum
// of equal opacity; the transmittance is exactly exp(-sigma rho 0.5).
TEST(SampleMarch, HomogeneousSlabExactOpacityAndStrata) {
  const float rho = 0.5f, sigma = 10.0f, step = 0.01f, jitter = 0.25f;
  const VolumeTexture v = slab(rho);
  SampleMarchInput in = straight_down(v, sigma, step);
  in.jitter = jitter;
  int cells = 0;
  std::vector<float> weights, depths;
  const SampleMarchResult r = march_samples(
      in, [&](const Cell&, int) { ++cells; },
      [&](const V3f& p, float w) {
        weights.push_back(w);
        depths.push_back(0.5f - p.z);
      });
  const int per_layer = 13;  // 0.125 / 0.01 rounded
  EXPECT_EQ(cells, 4);
  ASSERT_EQ(r.samples, 4 * per_layer);
  ASSERT_EQ(int(weights.size()), 4 * per_layer);
  const double tau_layer = double(sigma) * rho * 0.125, alpha = -std::expm1(-tau_layer);
  EXPECT_NEAR(r.transmittance, std::exp(-4.0 * tau_layer), 1e-6);
  for (int layer = 0; layer < 4; ++layer) {
    const double t_in = std::exp(-layer * tau_layer);
    for (int i = 0; i < per_layer; ++i) {
      const size_t at = size_t(layer * per_layer + i);
      EXPECT_NEAR(weights[at], t_in * alpha / per_layer, 1e-6);
      // The sample's opacity quantile inside its layer lies in its stratum.
      const double s = depths[at] - 0.125 * layer;
      const double u = -std::expm1(-double(sigma) * rho * s) / alpha;
      EXPECT_GE(u, double(i) / per_layer - 1e-4) << "layer " << layer << " sample " << i;
      EXPECT_LT(u, double(i + 1) / per_layer + 1e-4) << "layer " << layer << " sample " << i;
    }
  }
}

// Whatever the path through the cells (corners clipped, layers crossed
// obliquely, cells shorter than a step), the weights sum to the opacity
// 1 - T: every cell that absorbs also shines.
TEST(SampleMarch, WeightsSumToTheOpacityOnAnObliqueRay) {
  VolumeTexture v = slab(1.0f);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) v.at(i, j, k).density = float((i + 2 * j + 3 * k) % 5) * 0.3f;
  SampleMarchInput in = straight_down(v, 6.0f, 0.2f);  // a step longer than a layer
  in.dir_texture = V3f(0.61f, 0.43f, -0.3f).normalized();
  in.length_mm = distance_to_exit(v, in.entry_texture, in.dir_texture, march_cap_mm(v));
  for (float jitter : {0.0f, 0.3f, 0.9f}) {
    in.jitter = jitter;
    double sum = 0.0;
    const SampleMarchResult r =
        march_samples(in, [](const Cell&, int) {}, [&](const V3f&, float w) { sum += w; });
    EXPECT_GT(r.transmittance, 0.0f);
    EXPECT_NEAR(sum, 1.0 - r.transmittance, 1e-5) << "jitter " << jitter;
  }
}

// An opaque slab (sigma rho = 400 / mm, mean free path 2.5 um) marched at a
// step of 50 um, each sample lit by exp(-k depth), k = 400 / mm (a light
// straight above through the same fibre). The radiance is
// sigma / (sigma + k) = 0.5 (the slab is deep enough to be infinite).
// Equally spaced samples gave the mean of exp(-k s) over s in [0, step):
// 0.05, ten times too dark. The mean over jitters must be within five
// standard errors of 0.5.
TEST(SampleMarch, OpaqueSkinIsShadedAtItsMeanFreePathNotTheStep) {
  const VolumeTexture v = slab(40.0f);
  SampleMarchInput in = straight_down(v, 10.0f, 0.05f);
  in.cutoff = 1e-3f;
  const double k = 400.0;
  const int rays = 4000;
  double sum = 0.0, sum2 = 0.0;
  int samples = 0;
  for (int r = 0; r < rays; ++r) {
    in.jitter = (float(r) + 0.5f) / float(rays);
    double radiance = 0.0;
    const SampleMarchResult m = march_samples(
        in, [](const Cell&, int) {},
        [&](const V3f& p, float w) { radiance += w * std::exp(-k * (0.5 - p.z)); });
    samples += m.samples;
    sum += radiance;
    sum2 += radiance * radiance;
  }
  const double mean = sum / rays, se = std::sqrt(std::max(0.0, sum2 / rays - mean * mean) / rays);
  EXPECT_NEAR(mean, 0.5, 5.0 * se + 1e-6);
  // An opaque cell costs one sample, as an equally spaced march's first.
  EXPECT_EQ(samples, rays);
}

// The cutoff stops the march after the cell whose exit transmittance falls
// below it and reports 0; the roulette keeps the expected weight: over many
// seeds each sample's mean weight is T_in alpha / n.
TEST(SampleMarch, CutoffAndRouletteKeepTheExpectation) {
  const VolumeTexture v = slab(4.0f);  // tau 5 a layer
  SampleMarchInput in = straight_down(v, 10.0f, 0.01f);
  in.cutoff = 0.05f;
  int cells = 0;
  SampleMarchResult r =
      march_samples(in, [&](const Cell&, int) { ++cells; }, [](const V3f&, float) {});
  EXPECT_EQ(cells, 1);  // exp(-5) < 0.05 after the first layer
  EXPECT_EQ(r.transmittance, 0.0f);

  in.cutoff = 0.0f;
  in.length_mm = 0.125f;  // one layer: 13 strata of opacity alpha / 13
  in.roulette = 0.5f;
  const double alpha = -std::expm1(-5.0), share = alpha / 13.0;
  const int seeds = 20000;
  std::vector<double> mean(13, 0.0);
  // The callback sees only the samples the roulette keeps: file each weight
  // by its sample's opacity quantile, its stratum.
  for (int s = 0; s < seeds; ++s) {
    in.seed = uint64_t(s) * 0x9e3779b97f4a7c15ull + 1;
    in.jitter = (float(s % 97) + 0.5f) / 97.0f;  // off the strata's edges
    r = march_samples(in, [](const Cell&, int) {}, [&](const V3f& p, float w) {
      const double u = -std::expm1(-40.0 * (0.5 - double(p.z))) / alpha;
      mean[size_t(std::clamp(int(u * 13.0), 0, 12))] += w;
    });
    ASSERT_EQ(r.samples, 13);
  }
  for (int i = 0; i < 13; ++i) {
    const double t_front = 1.0 - i * share, p = std::min(1.0, t_front / 0.5);
    // Bernoulli(p) times share / p: standard error share sqrt((1 - p) / p / seeds).
    const double se = share * std::sqrt((1.0 - p) / p / seeds);
    EXPECT_NEAR(mean[size_t(i)] / seeds, share, 5.0 * se + 1e-7) << "stratum " << i;
  }
}

}  // namespace
}  // namespace clothbake
