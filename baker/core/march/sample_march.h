#pragma once
/// The skeleton every view march shares (PAPER.md s.5 steps 2 and 3): the
/// cells along the ray by DDA (cell_walk.h), equally spaced samples from
/// jitter * step, opacity 1 - exp(-sigma rho dt) per sample composited front
/// to back, Russian roulette on the lights behind a dim view, and the stop at
/// the cutoff. What a sample adds is the caller's: march_view_ray
/// (volume_march.h) lights it by the scene's lights, the material bake's
/// march (material/node_march.h) by every light node at once. Both call this
/// one loop, so they agree sample for sample by construction (pbrt-v4's
/// SampleT_maj takes its per-sample work as a callback the same way).

#include <cmath>
#include <cstdint>

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
  float jitter = 0.5f;  ///< first sample at jitter * step, jitter in [0, 1)
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

/// Marches `in`. For each cell with fibre that holds at least one sample,
/// `on_cell(cell, shaded)` is called first (`shaded`: samples before it, the
/// seed of a per-cell random choice), then for each of its samples whose
/// lights survive the roulette `on_sample(p_texture, weight)`, weight being
/// the view transmittance in front of the sample times its opacity times the
/// roulette's weight: the sample's radiance is its lit reflection times it.
template <typename OnCell, typename OnSample>
SampleMarchResult march_samples(const SampleMarchInput& in, OnCell&& on_cell,
                                OnSample&& on_sample) {
  float t_sample = in.jitter * in.step_mm;
  float transmittance = 1.0f;
  int shaded = 0;
  // Step 2 of the paper: the cells along the view ray, by DDA. Step 3: equally
  // spaced samples; empty cells are crossed without shading.
  auto visit = [&](const Cell& cell, float, float t1) {
    if (cell.density <= 0.0f) {
      if (t_sample < t1) t_sample += std::ceil((t1 - t_sample) / in.step_mm) * in.step_mm;
      return true;
    }
    const float alpha = 1.0f - std::exp(-in.extinction_per_mm * cell.density * in.step_mm);
    if (t_sample >= t1) return true;  // no sample falls in this cell
    // Tangent, light and eye directions are the same for every sample of one
    // cell: the caller computes the cell's reflection once.
    on_cell(cell, shaded);
    for (; t_sample < t1; t_sample += in.step_mm) {
      const Imath::V3f p_texture = in.entry_texture + in.dir_texture * t_sample;
      // Step 3a: behind a view already dimmer than `roulette` the sample adds
      // little, yet its shadow lookups cost as much as anywhere (they are most
      // of a render's time): they run with probability proportional to the
      // view transmittance, weighted by its inverse, so the expected radiance
      // is unchanged.
      float light_weight = 1.0f;
      if (transmittance < in.roulette) {
        const float p = transmittance / in.roulette;
        light_weight = unit_float(hash_key(in.seed, rng_stream::roulette, uint64_t(shaded))) < p
                           ? 1.0f / p
                           : 0.0f;
      }
      // Step 3b: weighted by the transmittance up to the sample.
      if (light_weight > 0.0f) on_sample(p_texture, transmittance * alpha * light_weight);
      transmittance *= 1.0f - alpha;
      ++shaded;
      // Step 3c: stop when nothing more can be seen.
      if (transmittance < in.cutoff) {
        transmittance = 0.0f;
        return false;
      }
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
