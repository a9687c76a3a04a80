#include "core/material_bake/material_source.h"

#include "core/material/material_shader.h"
#include "core/texture/volume_generator.h"
#include "core/weave/cloth_colours.h"

namespace clothbake {

std::string colour_parts_refusal(ShadingMode shading, bool from_vdb) {
  if (shading != ShadingMode::Fiber) return "isotropic shading has one albedo and no yarn colours";
  if (from_vdb) return "a volume read from a VDB file has its colours in its cells";
  return {};
}

namespace {
constexpr const char* k_rgb_asked = "RGB was asked (parts)";

/// The colour-free volume of `spec` (`volume` when generated already) into
/// `src`, with its spec and palette.
void make_colour_free(const ClothSpec& spec, uint64_t budget, MaterialSource& src,
                      std::shared_ptr<const VolumeTexture> volume = nullptr) {
  src.parts = MaterialParts::SpecularWarpWeft;
  src.cloth = colour_free(spec);
  src.palette = palette_of(spec);
  src.written_repeats = colour_free_repeats(spec);
  src.owned_volume =
      volume ? std::move(volume)
             : std::make_shared<const VolumeTexture>(generate_volume(src.cloth, budget));
  src.volume = src.owned_volume.get();
}
}  // namespace

std::shared_ptr<const VolumeTexture> colour_free_volume(const Scene& scene, int o,
                                                        uint64_t budget) {
  const ClothObject& obj = scene.objects[size_t(o)];
  if (!colour_parts_refusal(scene.settings.shading, obj.volume != nullptr).empty()) return nullptr;
  return std::make_shared<const VolumeTexture>(generate_volume(colour_free(obj.cloth), budget));
}

MaterialSource material_source(const ClothScene& prepared, int o, MaterialParts parts,
                               uint64_t budget, std::shared_ptr<const VolumeTexture> generated) {
  MaterialSource src;
  const Scene& scene = prepared.scene();
  const ClothObject& obj = scene.objects[size_t(o)];
  const ShadingSpec& shading = obj.cloth.shading;
  const RenderSettings& rs = scene.settings;
  src.optics = object_optics(prepared, o);
  src.owned_shader =
      make_object_fiber_shader(rs.fiber_model, shading.fiber_aspect, shading.exponent,
                               rs.fiber_samples, rs.seed, uint64_t(o));
  src.shader = src.owned_shader.get();
  src.rgb_reason = parts == MaterialParts::SpecularWarpWeft
                       ? colour_parts_refusal(src.optics.shading, obj.volume != nullptr)
                       : k_rgb_asked;
  if (src.rgb_reason.empty())
    make_colour_free(obj.cloth, budget, src, std::move(generated));
  else
    src.volume = &prepared.volume(o);
  return src;
}

MaterialSource material_source(const ClothSpec& spec, MaterialParts parts, uint64_t budget) {
  MaterialSource src;
  const MaterialOptics& o = src.optics;
  src.owned_shader =
      make_object_fiber_shader(o.fiber_model, spec.shading.fiber_aspect, spec.shading.exponent,
                               o.fiber_samples, o.fiber_seed, 0);
  src.shader = src.owned_shader.get();
  if (parts == MaterialParts::SpecularWarpWeft) {
    make_colour_free(spec, budget, src);
  } else {
    src.owned_volume = std::make_shared<const VolumeTexture>(generate_volume(spec, budget));
    src.volume = src.owned_volume.get();
    src.rgb_reason = k_rgb_asked;
  }
  return src;
}

MaterialSource material_source(const VolumeTexture& volume, const FiberShader& shader,
                               const MaterialOptics& optics) {
  MaterialSource src;
  src.volume = &volume;
  src.shader = &shader;
  src.optics = optics;
  src.rgb_reason = k_rgb_asked;
  return src;
}

MaterialSource material_source(const VolumeTexture& volume, const FiberShader& shader,
                               const MaterialOptics& optics, const ClothSpec& colour_free_cloth) {
  MaterialSource src = material_source(volume, shader, optics);
  src.parts = MaterialParts::SpecularWarpWeft;
  src.cloth = colour_free_cloth;
  src.palette = palette_of(colour_free_cloth);
  src.rgb_reason.clear();
  return src;
}

}  // namespace clothbake
