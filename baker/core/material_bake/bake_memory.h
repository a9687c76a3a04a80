#pragma once
/// The memory a material bake holds at its two high points, from its layout
/// and the ranks its factorisation reaches, so an estimate and the automatic
/// plan can say what a bake will take before it runs (material_bake.h):
///  - marching: the light fields (the whole repeat's, or one block window's
///    when addressed), the view matrices (one per thread for the whole
///    repeat; every view node's, held across the blocks, when addressed)
///    and the factors of the view nodes done so far;
///  - assembling: every view node's factors and the table they are copied
///    into, allocated at the largest rank for every view and level.
/// Neither counts the program and its volume, which the caller measures
/// (the process's resident bytes once its input is read).

#include <cstdint>

#include "core/material/cloth_material.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

/// The ranks an addressed bake reached at the defaults on the real drafts
/// of testscenes/wif/real (lab/real_drafts). Its high point is its view
/// matrices, so these move its estimate by a few per cent at most.
inline constexpr double k_expected_mean_rank = 20.0;
inline constexpr int k_expected_max_rank = 31;
/// The largest rank over all view nodes of a whole-repeat bake over the
/// largest of the estimate's probe lattice (material_probe.h).
inline constexpr double k_rank_probe_max_margin = 1.1;

/// The factorisation's ranks over the view nodes.
struct BakeRanks {
  double mean = 0.0;
  int max = 0;
};

/// The ranks an addressed bake of `material` is expected to reach: the
/// measured constants above, at most the light nodes.
BakeRanks expected_bake_ranks(const ClothMaterial& material);

struct BakeMemory {
  uint64_t marching = 0;    ///< fields, view matrices and the factors done
  uint64_t assembling = 0;  ///< every view's factors and the table at the largest rank
  uint64_t peak() const { return marching > assembling ? marching : assembling; }
};

/// The bytes of both high points of a bake of `material` (unbaked_material
/// with its cloth set) on `threads`, its factorisation at `ranks`.
BakeMemory bake_memory(const ClothMaterial& material, const VolumeTexture& volume, int threads,
                       const BakeRanks& ranks);

}  // namespace clothbake
