#pragma once
/// A cloth material applied to a prepared scene: what each object needs of a
/// material (its optics, measured from its mesh), the check that a material
/// fits, and the SurfaceShader lookup-render uses, which reads the material
/// at the pixel's footprint (mip level) under the scene's lights.

#include <string>
#include <vector>

#include "core/material/cloth_material.h"
#include "core/scene/cloth_scene.h"

namespace clothbake {

/// The optics an object of the prepared scene would bake a material with:
/// its extinction, the scene's shading settings, and the depth scale
/// measured from its mesh (the mean over quads, at their centres, of the
/// frame's mm_per_world.z over the geometric mean of .x and .y).
MaterialOptics object_optics(const ClothScene& prepared, int object);

/// How far an object's depth scale may differ from a material's before the
/// material is refused: beyond it, the fibre-shading angles drift (the march
/// path stays exact in texture space, docs/formats/material.md).
inline constexpr float k_depth_scale_tolerance = 0.05f;

/// Throws InputError on the first field in which `object` differs from what
/// the material was baked from: its cloth (the volume texture's hash), then
/// its optics (depth_scale as thickness_world, extinction_per_mm,
/// render.shading, render.fiber_model), naming the scene field and both values.
void check_material_fits(const ClothScene& prepared, int object, const ClothMaterial& material);

/// How wide a lookup's footprint is taken. Each of a pixel's spp stratified
/// samples prefilters its own stratum: the footprint is the pixel's width
/// times footprint_scale / sqrt(spp), so the samples' lookups together cover
/// the pixel once, whatever spp (docs/formats/material.md, "Reading it").
struct MaterialLookupSettings {
  float footprint_scale = 1.0f;
  ClothMaterial::LightFilter light_filter = ClothMaterial::LightFilter::CatmullRom;
};

/// The shader lookup-render uses: `materials[o]` for object o (all must be
/// set and outlive the shader).
SurfaceShader material_shader(const ClothScene& prepared,
                              const std::vector<const ClothMaterial*>& materials,
                              const MaterialLookupSettings& settings = {});

}  // namespace clothbake
