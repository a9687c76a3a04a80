#include "core/material_bake/bake_memory.h"

#include <algorithm>
#include <cmath>

#include "core/material_bake/material_bake.h"

namespace clothbake {

namespace {
/// One view node's factors at level 0 (factorisation.h): coefficients and
/// alpha per texel, the light factor per node.
double view_factor_bytes(const MaterialLayout& layout, double rank) {
  return (double(layout.level_texels(0)) * (double(layout.channels) * rank + 1.0) +
          double(layout.light_count()) * rank) *
         sizeof(float);
}
}  // namespace

BakeRanks expected_bake_ranks(const ClothMaterial& material) {
  const int L = material.light_count();
  const double mean = std::min(double(L), k_expected_mean_rank);
  const int max = std::min(L, k_expected_max_rank);
  return {mean, max};
}

BakeMemory bake_memory(const ClothMaterial& material, const VolumeTexture& volume, int threads,
                       const BakeRanks& ranks) {
  const MaterialLayout layout = material.layout();
  const double views = double(layout.view_count());
  const double factors = views * view_factor_bytes(layout, ranks.mean);
  const double per_thread = double(std::max(threads, 1)) * double(layout.view_matrix_bytes());
  BakeMemory m;
  const double fixed = double(material_bake_fixed_bytes(material, volume, threads));
  // The whole repeat holds its fields until every view node is factorised
  // (its fixed bytes hold a matrix per thread). An addressed bake holds
  // every view's matrix until the blocks are marched, then factorises them
  // one by one; the matrices it frees stay the process's (the allocator
  // keeps them for the factors that follow: measured on dbw_schort), so its
  // high point is all of it and a thread's copy each.
  m.marching = uint64_t(fixed + factors + (material.addressed() ? per_thread : 0.0));
  m.assembling = uint64_t(factors + double(layout.table_bytes(ranks.max)));
  return m;
}

}  // namespace clothbake
