#pragma once
/// What a material is baked from: a volume texture, the fibre shader its
/// cells are shaded with and the optics (material_settings.h), taken from a
/// scene's object as the renderer prepares it, or from a cloth spec alone.

#include <memory>
#include <string>

#include "core/fiber/fiber_shader.h"
#include "core/material/material_settings.h"
#include "core/material/yarn_colours.h"
#include "core/scene/cloth_scene.h"
#include "core/texture/volume_texture.h"
#include "core/weave/cloth_spec.h"

namespace clothbake {

struct MaterialSource {
  const VolumeTexture* volume = nullptr;
  std::shared_ptr<const VolumeTexture> owned_volume;  ///< a spec's; a scene's lives in the scene
  const FiberShader* shader = nullptr;
  std::unique_ptr<FiberShader> owned_shader;  ///< a scene's or a spec's; null when lent
  MaterialOptics optics;
  /// What the table's channels hold: colour-free parts when asked for and
  /// possible (fibre shading, a cloth generated from a spec), else RGB.
  MaterialParts parts = MaterialParts::Rgb;
  ClothSpec cloth;      ///< colour-free parts: the colour-free spec `volume` was generated from
  YarnPalette palette;  ///< colour-free parts: the cloth's own colours
  /// Colour-free parts: repeats of `cloth` in one repeat of the cloth's draft
  /// as written (colour_free_repeats, cloth_colours.h).
  Imath::V2f written_repeats{1.0f, 1.0f};
  /// RGB parts: why (colour_parts_refusal, or that RGB was asked), for a
  /// refusal that needs colour-free parts to say.
  std::string rgb_reason;
};

/// Whether a bake asked for colour-free parts gets them, and if not why
/// (empty when it does).
std::string colour_parts_refusal(ShadingMode shading, bool from_vdb);

/// Object `object` of the prepared scene (which must outlive the source):
/// its volume (or, for colour-free parts, its cloth made colour-free), the
/// fibre shader ClothScene builds for it and its optics (object_optics,
/// material_shader.h). `parts` is what is asked; RGB when colour-free parts
/// are not possible (source.parts says what was chosen).
/// `generated`, when given, is that cloth's colour-free volume
/// generated already (colour_free_volume below), which the source then shares.
MaterialSource material_source(const ClothScene& prepared, int object, MaterialParts parts,
                               uint64_t memory_budget_bytes,
                               std::shared_ptr<const VolumeTexture> generated = nullptr);

/// The colour-free volume of a scene's object `object`, or null when
/// colour-free parts are not possible for it (colour_parts_refusal). A reader
/// generates it before preparing the scene and lends it to ClothScene in
/// place of the object's own volume: the RGB volume, as large (10 GB for a
/// 641 x 641 draft at its default resolution), is then never generated, and
/// the quad patches take only the thickness from a generated volume, which
/// colours do not change.
std::shared_ptr<const VolumeTexture> colour_free_volume(const Scene& scene, int object,
                                                        uint64_t memory_budget_bytes);

/// A cloth spec alone: its generated volume, the default optics (depth scale
/// 1) and the fibre shader a one-object scene with the default render seed
/// would build.
MaterialSource material_source(const ClothSpec& spec, MaterialParts parts,
                               uint64_t memory_budget_bytes);

/// A volume and shader the caller holds (and which must outlive the source),
/// with RGB parts.
MaterialSource material_source(const VolumeTexture& volume, const FiberShader& shader,
                               const MaterialOptics& optics);
/// The same for a volume generated from `colour_free_cloth` (colour_free,
/// cloth_colours.h), with colour-free parts in that cloth's own colours.
MaterialSource material_source(const VolumeTexture& volume, const FiberShader& shader,
                               const MaterialOptics& optics, const ClothSpec& colour_free_cloth);

}  // namespace clothbake
