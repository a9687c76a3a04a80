#pragma once
/// What a material bake may be asked, stated once: the settings' ranges
/// (material_settings.h), which settings go together, and how many texels a
/// thread needs. The bake, the probe, the manifest reader and the command
/// line all ask here. Errors name the setting ("texels", "address"); a
/// front end maps it to its own word for it (a flag, a property).

#include "core/material/material_settings.h"
#include "core/material_bake/material_source.h"

namespace clothbake {

/// Throws InputError naming the field for a setting out of range.
void check_material_settings(const MaterialSettings& settings);

/// Throws InputError naming the setting when `settings` cannot be baked from
/// `source` as part `shard`: the ranges above; a depth scale that is not
/// positive and finite; colour-free parts without a colour-free cloth or
/// without fibre shading; a material addressed per crossing without
/// colour-free parts (its blocks and colours come from the cloth's threads)
/// or in shards (its blocks are not split by view node); a shard outside the
/// view nodes.
void check_material_bake(const MaterialSource& source, const MaterialSettings& settings,
                         const MaterialShard& shard);

/// Texels per thread below which the over-and-under of neighbouring threads
/// falls inside one texel (the paper cloth has 16).
inline constexpr double k_min_texels_per_thread = 2.0;
/// What the advice aims for when there are too few.
inline constexpr double k_advised_texels_per_thread = 4.0;

/// How finely the texels resolve the threads. Whole repeat: R texels span
/// every thread of the repeat, so a draft of many threads leaves few per
/// thread. Addressed per crossing: R texels span one thread, whatever the
/// repeat. Too few is advice, not a refusal: the bake is still the box
/// average of the cloth.
struct TexelAdvice {
  int threads_across = 0;          ///< threads a row of R texels spans (0: not known)
  double texels_per_thread = 0.0;  ///< R / threads_across (0: not known)
  /// The smallest power of 2 from R up, at most k_max_material_texels, that
  /// gives k_advised_texels_per_thread.
  int advised_texels = 0;
  bool known() const { return threads_across > 0; }
  bool too_few() const { return known() && texels_per_thread < k_min_texels_per_thread; }
};

/// The advice for `settings` on a repeat of `ends` warp ends and `picks`
/// weft picks (0: not known, as for a volume read from a VDB file).
TexelAdvice texel_advice(const MaterialSettings& settings, int ends, int picks);

}  // namespace clothbake
