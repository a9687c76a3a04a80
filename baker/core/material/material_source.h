#pragma once
/// What a material is baked from: a volume texture, the fibre shader its
/// cells are shaded with and the optics (material_settings.h), taken from a
/// scene's object as the renderer prepares it, or from a cloth spec alone.

#include <memory>

#include "core/fiber/fiber_shader.h"
#include "core/material/material_settings.h"
#include "core/scene/cloth_scene.h"
#include "core/texture/volume_texture.h"
#include "core/weave/cloth_spec.h"

namespace clothbake {

struct MaterialSource {
  const VolumeTexture* volume = nullptr;
  std::shared_ptr<const VolumeTexture> owned_volume;  ///< a spec's; a scene's lives in the scene
  std::unique_ptr<FiberShader> shader;
  MaterialOptics optics;
};

/// Object `object` of the prepared scene (which must outlive the source):
/// its volume, the fibre shader ClothScene builds for it and its optics
/// (object_optics, material_shader.h).
MaterialSource material_source(const ClothScene& prepared, int object);

/// A cloth spec alone: its generated volume, the default optics (depth scale
/// 1) and the fibre shader a one-object scene with the default render seed
/// would build.
MaterialSource material_source(const ClothSpec& spec, uint64_t memory_budget_bytes);

}  // namespace clothbake
