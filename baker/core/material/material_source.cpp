#include "core/material/material_source.h"

#include "core/material/material_shader.h"
#include "core/texture/volume_generator.h"

namespace clothbake {

MaterialSource material_source(const ClothScene& prepared, int o) {
  MaterialSource src;
  const Scene& scene = prepared.scene();
  const ShadingSpec& shading = scene.objects[size_t(o)].cloth.shading;
  const RenderSettings& rs = scene.settings;
  src.volume = &prepared.volume(o);
  src.optics = object_optics(prepared, o);
  src.shader = make_object_fiber_shader(rs.fiber_model, shading.fiber_aspect, shading.exponent,
                                        rs.fiber_samples, rs.seed, uint64_t(o));
  return src;
}

MaterialSource material_source(const ClothSpec& spec, uint64_t memory_budget_bytes) {
  MaterialSource src;
  src.owned_volume = std::make_shared<const VolumeTexture>(generate_volume(spec, memory_budget_bytes));
  src.volume = src.owned_volume.get();
  const MaterialOptics& o = src.optics;
  src.shader = make_object_fiber_shader(o.fiber_model, spec.shading.fiber_aspect,
                                        spec.shading.exponent, o.fiber_samples, o.fiber_seed, 0);
  return src;
}

}  // namespace clothbake
