#pragma once
/// A material bake split over machines (docs/guide/farm.md): part I of N bakes
/// only its share of the view nodes, every one exactly as the whole bake
/// would (each view node's samples are seeded by their own indices and it is
/// factorised alone), so joining the parts gives the whole bake's bytes.
///
/// The views are dealt by an estimate of their cost, longest first, each to
/// the part with the least so far: a grazing view marches farther through
/// the slab than a head-on one, so dealing by index would leave one part
/// with the horizon.

#include <span>
#include <vector>

#include "core/material/cloth_material.h"

namespace clothbake {

/// Throws InputError on "shard" unless 0 <= index < count and count is in
/// [1, the view nodes].
void check_material_shard(const MaterialShard& shard, int view_count);

/// The view nodes part `shard` bakes, ascending. Over the parts of one count
/// each view node appears exactly once.
std::vector<int> material_shard_views(const DirectionGrid& view_grid, const MaterialShard& shard);

/// The estimated relative cost of baking view node `view`: one for the
/// factorisation and the texel loop, plus the march's length through a slab,
/// 1 / cos(theta), bounded where the march's cutoff ends it.
double material_view_cost(const DirectionGrid& view_grid, int view);

/// Copies view nodes `views` of `part` (every level, alpha, coefficients,
/// light factors, rank and error) into `whole`, which has the same layout and
/// a max_rank at least the part's.
void copy_material_views(const ClothMaterial& part, std::span<const int> views,
                         ClothMaterial& whole);

}  // namespace clothbake
