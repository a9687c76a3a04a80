#include "core/march/volume_march.h"

#include <cmath>
#include <numbers>

#include "core/march/cell_walk.h"
#include "core/util/random.h"

namespace clothbake {

namespace {
using Imath::V3f;
constexpr float k_inv_4pi = 0.25f / std::numbers::pi_v<float>;
}  // namespace

MarchResult march_view_ray(const MarchInput& in) {
  MarchResult out;
  const VolumeTexture& volume = *in.volume;
  float t_sample = in.jitter * in.step_mm;
  float transmittance = 1.0f;
  V3f radiance(0.0f);
  int shaded = 0;

  // Step 2 of the paper: the cells along the view ray, by DDA. Step 3: equally
  // spaced samples; empty cells are crossed without shading.
  auto shade_cell = [&](const Cell& cell, float, float t1) {
    if (cell.density <= 0.0f) {
      if (t_sample < t1) t_sample += std::ceil((t1 - t_sample) / in.step_mm) * in.step_mm;
      return true;
    }
    const float alpha = 1.0f - std::exp(-in.extinction_per_mm * cell.density * in.step_mm);
    if (t_sample >= t1) return true;  // no sample falls in this cell
    const V3f tangent_local =
        V3f(cell.tangent.x / in.mm_per_world.x, cell.tangent.y / in.mm_per_world.y,
            cell.tangent.z / in.mm_per_world.z)
            .normalized();
    // Tangent, light and eye directions are the same for every
    // sample of one cell: the cell's reflection per light is
    // computed once; only the light's transmittance varies.
    V3f reflect[k_max_march_lights];
    const size_t n_lights = std::min(in.lights.size(), k_max_march_lights);
    for (size_t l = 0; l < n_lights; ++l) {
      if (in.shading == ShadingMode::Isotropic) {
        reflect[l] = in.isotropic_albedo * k_inv_4pi;
      } else {
        const FiberResponse f =
            in.shader->eval(tangent_local, in.lights[l].to_light_local, in.to_eye_local,
                            hash_key(in.seed, uint64_t(shaded)));
        reflect[l] = cell.diffuse * f.diffuse + V3f(cell.specular * f.specular);
      }
    }
    for (; t_sample < t1; t_sample += in.step_mm) {
      const V3f p_texture = in.entry_texture + in.dir_texture * t_sample;
      // Step 3a: light reaching the sample from each light. Behind a
      // view already dimmer than `roulette` the sample adds little, yet
      // its shadow marches cost as much as anywhere (they are most of a
      // render's time): they run with probability proportional to the
      // view transmittance, weighted by its inverse, so the expected
      // radiance is unchanged.
      float light_weight = 1.0f;
      if (transmittance < in.roulette) {
        const float p = transmittance / in.roulette;
        light_weight = unit_float(hash_key(in.seed, rng_stream::roulette, uint64_t(shaded))) < p
                           ? 1.0f / p
                           : 0.0f;
      }
      if (light_weight > 0.0f) {
        V3f scattered(0.0f);
        for (size_t l = 0; l < n_lights; ++l) {
          const MarchLight& light = in.lights[l];
          const float t_light =
              light.cache ? TransmittanceCache::transmittance(light.cache->march_then_lookup(
                                volume, p_texture, light.to_light_texture, in.extinction_per_mm))
                          : shadow_transmittance(volume, p_texture, light.to_light_texture,
                                                 in.extinction_per_mm);
          if (t_light > 0.0f) scattered += light.irradiance * reflect[l] * t_light;
        }
        // Step 3b: weighted by the transmittance up to the sample.
        radiance += scattered * (transmittance * alpha * light_weight);
      }
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
  walk_cells(volume, in.entry_texture, in.dir_texture, in.length_mm, shade_cell);
  out.radiance = radiance;
  out.transmittance = transmittance;
  out.samples = shaded;
  return out;
}

}  // namespace clothbake
