#pragma once
/// The skeleton every view march shares (PAPER.md s.5 steps 2 and 3): the
/// cells along the ray by DDA (cell_walk.h), each cell's exact opacity
/// 1 - exp(-sigma rho length) composited front to back and shared among
/// samples placed by its extinction (about one a step), Russian roulette on
/// the lights behind a dim view, and the stop at the cutoff. What a sample
/// adds is the caller's: march_view_ray
/// (volume_march.h) lights it by the scene's lights, the material bake's
/// march (material/node_march.h) by every light node at once. Both call this
/// one loop, so they agree sample for sample by construction (pbrt-v4's
/// SampleT_maj takes its per-sample work as a callback the same way).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Imath/ImathVec.h>

#include "core/march/cell_walk.h"
#include "core/texture/volume_texture.h"
#include "core/util/random.h"

namespace clothbake {

/// The ray and the sampling of one view march, in texture space.
struct SampleMarchInput {
  const VolumeTexture* volume = nullptr;
  Imath::V3f entry_texture;  ///< where the ray enters the volume (top face, or bottom from behind)
  Imath::V3f dir_texture;    ///< unit, texture space
  float length_mm = 0.0f;    ///< length of the ray inside the volume
  float extinction_per_mm = 40.0f;
  float step_mm = 0.01f;
  float cutoff = 1e-3f;
  /// In [0, 1): the first cell's samples sit at (i + jitter) / n of its
  /// opacity; each further cell's offset turns by the golden ratio.
  float jitter = 0.5f;
  uint64_t seed = 0;    ///< for the direct ellipsoid model's jitter and the roulette
  /// Russian roulette on the light: once the view transmittance in front of a
  /// sample is below this, its lights are evaluated only with probability
  /// transmittance / roulette (and then weighted by the inverse). 0: always.
  float roulette = 0.0f;
};

struct SampleMarchResult {
  float transmittance = 1.0f;  ///< un-absorbed fraction (0 when stopped at the cutoff)
  int samples = 0;             ///< samples shaded (with fibre in their cell)
};

/// Marches `in`. For each cell with fibre the ray crosses,
/// `on_cell(cell, shaded)` is called first (`shaded`: samples before it, the
/// seed of a per-cell random choice), then for each of its samples whose
/// lights survive the roulette `on_sample(p_texture, weight)`, weight being
/// the view transmittance at the cell's entry times the sample's share of
/// the cell's opacity times the roulette's weight: the sample's radiance is
/// its lit reflection times it.
template <typename OnCell, typename OnSample>
SampleMarchResult march_samples(const SampleMarchInput& in, OnCell&& on_cell,
                                OnSample&& on_sample) {
  // Golden-ratio rotation of the ray's jitter from one cell to the next: each
  // cell's samples get their own stratification offset at no cost of a hash.
  constexpr float k_golden = 0.618034f;
  const float inv_step = 1.0f / in.step_mm;
  float transmittance = 1.0f;
  float offset = in.jitter;
  int shaded = 0;
  // Step 2 of the paper: the cells along the view ray, by DDA. Empty cells are
  // crossed without shading.
  auto visit = [&](const Cell& cell, float t0, float t1) {
    if (cell.density <= 0.0f) return true;
    // A cell's density is constant, so its opacity over the segment is exact.
    const float sigma = in.extinction_per_mm * cell.density;
    const float length = t1 - t0;
    const float alpha = -std::expm1(-sigma * length);
    if (!(alpha > 0.0f)) return true;
    // Step 3, samples placed by the cell's extinction rather than equally
    // spaced: depth s in [0, length] is drawn with density
    // sigma exp(-sigma s) / alpha, stratified in n strata of equal opacity, so
    // each sample carries alpha / n of the cell and the estimate is unbiased
    // whatever the step. Equally spaced samples shaded an opaque yarn at a
    // depth uniform in [0, step), below the skin the light reaches, and
    // darkened every route by the step (docs/design/renderer.md, "The march's
    // samples").
    //
    // n is the cell's length in steps, rounded (the samples an equally spaced
    // march puts there on average), at most the samples such a march shades
    // before the cutoff (an opaque cell costs one sample), and at least one:
    // a cell that absorbs also shines. That one sample in a clipped corner
    // costs 10 % more samples on the paper cloth and buys far more than 10 %
    // more pixel samples would; shading such corners by chance (probability
    // p, weight 1 / p) was the cheaper estimator that lost
    // (docs/design/renderer.md, "The march's samples").
    const float tau_to_cutoff =
        in.cutoff > 0.0f ? std::log(transmittance / in.cutoff) : std::numeric_limits<float>::max();
    const float by_length = length * inv_step + 0.5f;
    const float by_cutoff = std::ceil(tau_to_cutoff / (sigma * in.step_mm));
    const int n = std::max(1, int(std::min({by_length, by_cutoff, 1e6f})));
    const float share = alpha / float(n);
    // Tangent, light and eye directions are the same for every sample of one
    // cell: the caller computes the cell's reflection once.
    on_cell(cell, shaded);
    for (int i = 0; i < n; ++i) {
      const float u = (float(i) + offset) / float(n);
      const float s = std::min(length, -std::log1p(-u * alpha) / sigma);
      const Imath::V3f p_texture = in.entry_texture + in.dir_texture * (t0 + s);
      // Step 3a: behind a view already dimmer than `roulette` the sample adds
      // little, yet its shadow lookups cost as much as anywhere (they are most
      // of a render's time): they run with probability proportional to the
      // view transmittance in front of the sample's stratum, weighted by its
      // inverse, so the expected radiance is unchanged.
      float light_weight = 1.0f;
      const float t_front = transmittance * (1.0f - float(i) * share);
      if (t_front < in.roulette) {
        const float p = t_front / in.roulette;
        light_weight = unit_float(hash_key(in.seed, rng_stream::roulette, uint64_t(shaded))) < p
                           ? 1.0f / p
                           : 0.0f;
      }
      // Step 3b: weighted by the view transmittance at the cell's entry and
      // the sample's share of the cell's opacity.
      if (light_weight > 0.0f) on_sample(p_texture, transmittance * share * light_weight);
      ++shaded;
    }
    offset += k_golden;
    if (offset >= 1.0f) offset -= 1.0f;
    transmittance *= 1.0f - alpha;
    // Step 3c: stop when nothing more can be seen.
    if (transmittance < in.cutoff) {
      transmittance = 0.0f;
      return false;
    }
    return true;
  };
  walk_cells(*in.volume, in.entry_texture, in.dir_texture, in.length_mm, visit);
  return SampleMarchResult{transmittance, shaded};
}

/// Where a view ray through the top-face point `top_texture` runs inside the
/// slab (the map m's entry, PAPER.md s.4): from the front (d.z < 0) down from
/// the top face to the face it leaves by; from behind (d.z > 0) up from the
/// bottom face to the hit. A ray along the faces (d.z = 0) has no length.
struct SlabEntry {
  Imath::V3f entry_texture;
  float length_mm = 0.0f;
};
inline SlabEntry slab_entry(const VolumeTexture& volume, const Imath::V3f& top_texture,
                            const Imath::V3f& dir_texture) {
  const float cap = march_cap_mm(volume);
  SlabEntry e{top_texture, 0.0f};
  if (dir_texture.z < 0.0f) {
    e.length_mm = distance_to_exit(volume, top_texture, dir_texture, cap);
  } else if (dir_texture.z > 0.0f) {
    e.length_mm = std::min(cap, volume.size_mm().z / dir_texture.z);
    e.entry_texture = top_texture - dir_texture * e.length_mm;
    // A grazing view from behind (within ~0.3 degrees of the horizon) is capped:
    // the march must still start at the bottom face, the side the eye sees, not
    // `cap` before the hit inside the volume, nearer the lit top (that was up to
    // 5.8 x too bright, tests/core/stability_test.cpp). Only the far end is cut.
    e.entry_texture.z = 0.0f;
  }
  return e;
}

}  // namespace clothbake
