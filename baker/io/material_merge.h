#pragma once
/// Joining the parts of a sharded material bake (`clothbake material
/// --shard I/N`, material_shard.h) into the whole material, whose folder
/// then has the bytes an unsharded bake writes.

#include <cstdint>
#include <string>
#include <vector>

#include "core/material/cloth_material.h"
#include "io/material_io.h"

namespace clothbake::io {

/// Reads every part's manifest first and refuses, naming the folder and the
/// field, parts that do not belong together: a whole material among them,
/// any manifest field but the per-view ones (shard, ranks, errors, max_rank,
/// bake counts) that differs, parts of another count, a part given twice or
/// one missing. Then reads the parts one at a time into the whole material.
/// `info` takes the first part's names and the bake counts summed.
ClothMaterial merge_material_parts(const std::vector<std::string>& dirs, MaterialInfo& info,
                                   uint64_t memory_budget_bytes = uint64_t(1) << 40);

}  // namespace clothbake::io
