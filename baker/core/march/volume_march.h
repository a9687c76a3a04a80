#pragma once
/// The view-ray march of Kimoto & Ohno section 5 (PAPER.md s.5) through one
/// volume texture, in texture space: the skeleton of sample_march.h (cells by
/// DDA, each cell's exact opacity composited front to back and shared among
/// samples placed by its extinction), each sample lit by every light through
/// the cloth and shaded.

#include <cstdint>
#include <span>

#include <Imath/ImathVec.h>

#include "core/fiber/fiber_shader.h"
#include "core/march/light_transmittance.h"
#include "core/march/march_settings.h"
#include "core/march/sample_march.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

/// Lights one march handles (more are ignored; the scene reader refuses them).
inline constexpr size_t k_max_march_lights = 8;

/// One light as seen from the march's quad.
struct MarchLight {
  Imath::V3f to_light_texture;  ///< unit, texture space: the shadow march direction
  Imath::V3f to_light_local;    ///< unit, local orthonormal frame: for shading
  Imath::V3f irradiance;        ///< arriving at the cloth, before the cloth's own attenuation
  const TransmittanceCache* cache = nullptr;  ///< null: march toward the light at every sample
  float cache_depth_scale = 1.0f;  ///< TransmittanceCache::depth_scale_for(to_light_texture)
};

/// A view march of the scene's lights: the ray and its sampling
/// (sample_march.h), and what each sample is lit and shaded by.
struct MarchInput : SampleMarchInput {
  const FiberShader* shader = nullptr;
  Imath::V3f to_eye_local;  ///< unit, local frame
  Imath::V3f mm_per_world;  ///< the frame's scales: carry fibre tangents to the local frame
  std::span<const MarchLight> lights;
  ShadingMode shading = ShadingMode::Fiber;
  Imath::V3f isotropic_albedo{0.8f, 0.8f, 0.8f};
};

struct MarchResult {
  Imath::V3f radiance{0, 0, 0};  ///< light leaving toward the eye
  float transmittance =
      1.0f;         ///< un-absorbed fraction: the see-through (0 when stopped at the cutoff)
  int samples = 0;  ///< samples shaded (with fibre in their cell)
};

MarchResult march_view_ray(const MarchInput& in);

}  // namespace clothbake
