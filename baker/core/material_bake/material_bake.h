#pragma once
/// The material bake: one weave repeat's appearance for every view node,
/// light node and texel (docs/formats/material.md), computed from the volume
/// texture alone (no scene, no lights, no mesh):
///  1. the transmittance toward every light node, one field each over the
///     repeat (light_fields.h);
///  2. per view node, each texel's jittered samples marched once for all
///     light nodes (node_march.h) into a texels x RGB by light-node matrix;
///  3. that matrix factorised (truncated SVD through its Gram matrix) to the
///     smallest rank whose relative error meets `max_error`;
///  4. the mip levels, box averages of level 0.
/// Deterministic for any thread count: every texel sample is seeded by its
/// own indices and each view node is factorised by one thread.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/material/cloth_material.h"
#include "core/material/material_settings.h"
#include "core/material_bake/material_source.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

struct MaterialBakeStats {
  uint64_t rays = 0;               ///< view marches (texels x spp x view nodes)
  uint64_t march_samples = 0;      ///< view samples shaded
  uint64_t fiber_evaluations = 0;  ///< cells x light nodes
  uint64_t field_bytes = 0;        ///< the light fields
  double uncompressed_values = 0;  ///< texels x views x lights x RGB at level 0, before the SVD
  /// Wall seconds of the steps, named as material_probe.h estimates them:
  /// the light fields' build, the marches (with the fibre tables), the
  /// factorisation, and the table's assembly with its mips. Over the whole
  /// repeat a view node is marched and factorised in one task; the tasks'
  /// wall time is split between the two by their CPU time.
  double fields_seconds = 0.0, marches_seconds = 0.0, factorise_seconds = 0.0,
         assemble_seconds = 0.0;
};

/// The light fields the bake holds at once: the whole repeat's, or the
/// largest block window's when addressed.
uint64_t material_field_bytes(const ClothMaterial& material, const VolumeTexture& volume);

/// Bytes the bake holds before the factorised table grows: the light fields
/// (the blocks' windows when addressed) and one view's matrix per thread.
/// `material`: unbaked_material with its cloth set.
uint64_t material_bake_fixed_bytes(const ClothMaterial& material, const VolumeTexture& volume,
                                   int threads);

/// Bakes the material `source` is of with `settings`, or part `shard` of it
/// (its view nodes only, material_shard.h). Throws InputError naming the
/// setting for what cannot be baked (check_material_bake, bake_rules.h).
/// Colour-free parts (settings.parts) take the threads of the source's
/// colour-free cloth (they decide which parts are a sample's own and which
/// its neighbours') and its colours as the material's own.
/// `memory_budget_bytes` bounds the fields plus the factorised table as it
/// grows (InputError on "memory" when exceeded). `progress(fraction)` is
/// called serialised from workers.
ClothMaterial bake_material(const MaterialSource& source, const MaterialSettings& settings,
                            uint64_t memory_budget_bytes,
                            const std::function<void(double)>& progress = {},
                            MaterialBakeStats* stats = nullptr, const MaterialShard& shard = {});

/// The ranks the factorisation reaches on view nodes `views` of a bake of
/// `material` (unbaked_material of `source`, the whole repeat), each marched
/// and factorised as the bake does under the whole repeat's light fields
/// (at k_rank_probe_field_supersample): the estimate's probe of the table's
/// size. Costs the fields' build and those views' marches.
inline constexpr int k_rank_probe_field_supersample = 1;
std::vector<int> probe_view_ranks(const MaterialSource& source, const ClothMaterial& material,
                                  std::span<const int> views);

/// Throws InputError on "memory" when the bytes the bake holds before its
/// table grows (material_bake_fixed_bytes) exceed `memory_budget_bytes`.
void check_material_memory(const ClothMaterial& material, const VolumeTexture& volume, int threads,
                           uint64_t memory_budget_bytes);

/// A material with the settings' grids, the volume's extent and hash, and
/// no table: what bake_material fills.
ClothMaterial unbaked_material(const VolumeTexture& volume, const MaterialOptics& optics,
                               const MaterialSettings& settings);
/// The same for `source`'s volume and optics, with its colour-free cloth, its
/// colours and written repeats set when the settings ask colour-free parts.
ClothMaterial unbaked_material(const MaterialSource& source, const MaterialSettings& settings);

/// Whether the bake tabulates the fibre response per view node
/// (FiberLightTable) rather than evaluating the model per cell.
bool tabulates_fiber(const MaterialSettings& settings, const MaterialOptics& optics);

}  // namespace clothbake
