#include "core/march/volume_march.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/util/random.h"

namespace clothbake {

namespace {
using Imath::V3f;
constexpr float k_inv_4pi = 0.25f / std::numbers::pi_v<float>;
}  // namespace

MarchResult march_view_ray(const MarchInput& in) {
  const VolumeTexture& volume = *in.volume;
  const size_t n_lights = std::min(in.lights.size(), k_max_march_lights);
  V3f radiance(0.0f);
  // The cell's reflection per light, computed once per cell: tangent, light
  // and eye directions are the same for every sample of one cell; only the
  // light's transmittance varies.
  V3f reflect[k_max_march_lights];
  auto shade_cell = [&](const Cell& cell, int shaded) {
    const V3f tangent_local =
        V3f(cell.tangent.x / in.mm_per_world.x, cell.tangent.y / in.mm_per_world.y,
            cell.tangent.z / in.mm_per_world.z)
            .normalized();
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
  };
  // Step 3a of the paper: light reaching the sample from each light.
  auto light_sample = [&](const V3f& p_texture, float weight) {
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
    radiance += scattered * weight;
  };
  const SampleMarchResult r = march_samples(in, shade_cell, light_sample);
  MarchResult out;
  out.radiance = radiance;
  out.transmittance = r.transmittance;
  out.samples = r.samples;
  return out;
}

}  // namespace clothbake
