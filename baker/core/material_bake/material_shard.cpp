#include "core/material_bake/material_shard.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/util/error.h"

namespace clothbake {

void check_material_shard(const MaterialShard& shard, int view_count) {
  if (shard.count < 1 || shard.count > view_count)
    throw InputError("shard", "the count must be in [1, " + std::to_string(view_count) +
                                  "] (one view node per part at most), got " +
                                  std::to_string(shard.count));
  if (shard.index < 0 || shard.index >= shard.count)
    throw InputError("shard", "part " + std::to_string(shard.index + 1) + " of " +
                                  std::to_string(shard.count) + " does not exist");
}

double material_view_cost(const DirectionGrid& view_grid, int view) {
  // Past 1 / cos = 8 (83 degrees) the march's transmittance cutoff, not the
  // slab, ends most rays; the bound keeps the horizon from weighing as if
  // its rays were endless.
  constexpr double k_max_path = 8.0;
  const double cos_theta = std::fabs(double(view_grid.bake_direction(view).z));
  return 1.0 + std::min(k_max_path, 1.0 / std::max(cos_theta, 1.0 / k_max_path));
}

std::vector<int> material_shard_views(const DirectionGrid& view_grid, const MaterialShard& shard) {
  const int n = 2 * view_grid.nodes_per_side();
  check_material_shard(shard, n);
  // Longest first, each to the least-loaded part (ties: the lower view
  // index, then the lower part): deterministic, and within one view's cost
  // of the best split.
  std::vector<double> cost(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) cost[size_t(v)] = material_view_cost(view_grid, v);
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return cost[size_t(a)] > cost[size_t(b)]; });
  std::vector<double> load(size_t(shard.count), 0.0);
  std::vector<int> mine;
  for (const int v : order) {
    const size_t part = size_t(std::min_element(load.begin(), load.end()) - load.begin());
    load[part] += cost[size_t(v)];
    if (int(part) == shard.index) mine.push_back(v);
  }
  std::sort(mine.begin(), mine.end());
  return mine;
}

void copy_material_views(const ClothMaterial& part, std::span<const int> views,
                         ClothMaterial& whole) {
  const size_t rp = size_t(part.max_rank), rw = size_t(whole.max_rank);
  const size_t n_lights = size_t(whole.light_count());
  for (const int v : views) {
    const size_t vi = size_t(v);
    whole.rank[vi] = part.rank[vi];
    whole.error[vi] = part.error[vi];
    for (int l = 0; l < whole.levels(); ++l) {
      const size_t texels = whole.layout().level_texels(l);
      std::copy_n(part.alpha[l].begin() + ptrdiff_t(vi * texels), texels,
                  whole.alpha[l].begin() + ptrdiff_t(vi * texels));
      for (size_t t = 0; t < texels; ++t)
        for (size_t k = 0; k < rp; ++k) {
          whole.coefficients[l][(vi * texels + t) * rw + k] =
              part.coefficients[l][(vi * texels + t) * rp + k];
          if (whole.colour_parts())
            whole.coefficients_next[l][(vi * texels + t) * rw + k] =
                part.coefficients_next[l][(vi * texels + t) * rp + k];
        }
    }
    for (size_t n = 0; n < n_lights; ++n)
      for (size_t k = 0; k < rp; ++k)
        whole.light_factors[(vi * n_lights + n) * rw + k] =
            part.light_factors[(vi * n_lights + n) * rp + k];
  }
}

}  // namespace clothbake
