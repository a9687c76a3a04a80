#pragma once
/// The baker: evaluates the prepared scene's march (ClothScene::shade_surface)
/// per texel of each quad and per view direction of a hemisphere grid, into a
/// LookupTable that a renderer without volumes can apply (docs/formats/lookup.md).
///
/// A full bake (every quad, every direction node of both sides, `texels` per
/// quad side) serves any camera. An adaptive bake derives everything from the
/// scene's camera: only quads the camera sees, texels from each quad's
/// projected size, and only the direction nodes its view directions fall
/// between (the four each bilinear lookup reads).

#include <cstdint>
#include <functional>
#include <vector>

#include "core/bake/bake_settings.h"
#include "core/bake/lookup_table.h"
#include "core/scene/cloth_scene.h"

namespace clothbake {

/// What a bake computes, per object. Unseen quads have size 0; nodes not
/// needed are not baked and get no square; quads outside the subset keep
/// their squares (the whole bake's layout) but are not baked.
struct BakePlan {
  std::vector<LookupTable> objects;           ///< layout and baked flags filled, atlases empty
  uint64_t texel_direction_samples = 0;       ///< texels x directions x spp to evaluate
  uint64_t full_texel_direction_samples = 0;  ///< the same for a full bake at BakeSettings::texels
  uint64_t baked_nodes = 0,
           full_nodes = 0;               ///< direction tiles (quad x node) baked / in a full bake
  uint64_t texels = 0, full_texels = 0;  ///< texels per direction, summed over quads
};

/// Plans the bake; throws InputError for settings out of range.
BakePlan plan_bake(const ClothScene& prepared, const BakeSettings& settings);

/// Runs a plan: fills every planned texel of every planned node, then the
/// gutters. Deterministic for any thread count. `progress(fraction)` is
/// called serialised from workers.
std::vector<LookupTable> run_bake(ClothScene& prepared, const BakePlan& plan,
                                  const BakeSettings& settings,
                                  const std::function<void(double)>& progress = {});

/// One march sample of a plan: texel (a, b) of a quad toward a direction
/// node, sub-texel sample k (run_bake averages k = 0 .. spp - 1).
struct BakeSample {
  int object = 0, quad = 0, node = 0, a = 0, b = 0, k = 0;
};

/// `n` of the plan's march samples (all of them if it plans fewer), spread
/// evenly over them: the planned samples, ordered by object, quad, node,
/// texel and sample, cut into n equal runs, one sample drawn from each at a
/// hashed offset, so that quads and nodes (grazing and steep) appear in
/// proportion to their share of the work, without aliasing with the texel
/// grid. Deterministic (from the seed); in that order.
std::vector<BakeSample> probe_samples(const BakePlan& plan, const BakeSettings& settings,
                                      uint64_t n);

/// Evaluates `samples` exactly as run_bake does (same seeds, same march,
/// light caches prepared first), in parallel; results in the same order.
std::vector<MarchResult> evaluate_bake_samples(ClothScene& prepared, const BakePlan& plan,
                                               const BakeSettings& settings,
                                               const std::vector<BakeSample>& samples);

/// The probe behind `clothbake bake --estimate`: evaluates probe_samples(n)
/// and returns how many it evaluated. The caller times it (the core keeps
/// no clock) and scales by plan.texel_direction_samples / that count.
/// Prepares the light caches first, as run_bake does: a caller timing the
/// march alone calls prepared.prepare_light_caches() before.
uint64_t probe_bake(ClothScene& prepared, const BakePlan& plan, const BakeSettings& settings,
                    uint64_t n);

/// The shader lookup-render uses: reads `tables` the way the Blender add-on
/// does (bilinear texels, bilinear directions). Unbaked lookups read as
/// transparent and are counted in `misses`.
SurfaceShader lookup_shader(const ClothScene& prepared, const std::vector<LookupTable>& tables,
                            std::atomic<uint64_t>* misses);

}  // namespace clothbake
