#include "core/material_bake/bake_rules.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/material/material_layout.h"
#include "core/material_bake/material_shard.h"
#include "core/util/error.h"

namespace clothbake {

namespace {
bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }
}  // namespace

void check_material_settings(const MaterialSettings& s) {
  auto range = [](const std::string& field, int value, int lo, int hi) {
    if (value < lo || value > hi)
      throw InputError(field, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                  "], got " + std::to_string(value));
  };
  range("texels", s.texels, k_min_material_texels, k_max_material_texels);
  if (!power_of_two(s.texels))
    throw InputError("texels", "must be a power of 2 (the mip levels halve it down to 1), got " +
                                   std::to_string(s.texels));
  range("directions", s.directions, k_min_material_directions, k_max_material_directions);
  range("light_directions", s.light_directions, k_min_material_directions,
        k_max_material_directions);
  range("spp", s.spp, k_min_material_spp, k_max_material_spp);
  range("context", s.context, k_min_material_context, k_max_material_context);
  range("members", s.members, k_min_material_members, k_max_material_members);
  range("phase_bins", s.phase_bins, k_min_phase_bins, k_max_phase_bins);
  range("field_supersample", s.field_supersample, k_min_field_supersample, k_max_field_supersample);
  if (s.fiber_tangent_nodes != 0)
    range("fiber_tangent_nodes", s.fiber_tangent_nodes, k_min_fiber_tangent_nodes,
          k_max_fiber_tangent_nodes);
  if (!(s.max_error >= k_min_material_error && s.max_error <= k_max_material_error))
    throw InputError("max_error", "must be in [0, 1], got " + std::to_string(s.max_error));
}

void check_material_bake(const MaterialSource& source, const MaterialSettings& settings,
                         const MaterialShard& shard) {
  check_material_settings(settings);
  const bool colour_parts = settings.parts == MaterialParts::SpecularWarpWeft;
  if (colour_parts && source.parts != MaterialParts::SpecularWarpWeft)
    throw InputError("parts", "colour-free parts need the colour-free cloth the volume is of");
  if (!(source.optics.depth_scale > 0.0f) || !std::isfinite(source.optics.depth_scale))
    throw InputError("depth_scale", "must be positive and finite");
  if (colour_parts && source.optics.shading != ShadingMode::Fiber)
    throw InputError("parts",
                     "colour-free parts need fibre shading (isotropic shading has one "
                     "albedo and no yarn colours)");
  if (settings.address == MaterialAddress::Crossings) {
    if (!colour_parts)
      throw InputError("address",
                       "crossings needs colour-free parts (its blocks and colours "
                       "come from the cloth's threads); this bake stores RGB: " +
                           source.rgb_reason);
    if (!shard.whole())
      throw InputError("shard", "a material addressed per crossing is baked whole");
  }
  try {
    check_material_shard(shard, MaterialLayout::of(settings).view_count());
  } catch (const InputError& e) {
    throw InputError("shard",
                     e.message() + " (directions " + std::to_string(settings.directions) + ")");
  }
}

TexelAdvice texel_advice(const MaterialSettings& settings, int ends, int picks) {
  TexelAdvice a;
  a.threads_across = settings.address == MaterialAddress::Crossings ? 1 : std::max(ends, picks);
  if (!a.known()) return a;
  a.texels_per_thread = double(settings.texels) / a.threads_across;
  a.advised_texels = settings.texels;
  while (a.advised_texels < k_max_material_texels &&
         double(a.advised_texels) / a.threads_across < k_advised_texels_per_thread)
    a.advised_texels *= 2;
  return a;
}

}  // namespace clothbake
