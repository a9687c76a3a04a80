#include "core/bake/lookup_merge.h"

#include <algorithm>

namespace clothbake {

/// The first layout field in which two tables of one K differ (empty if none):
/// parts of one bake share everything but their flags and texels.
std::string layout_mismatch(const LookupTable& a, const LookupTable& b) {
  if (a.gutter != b.gutter) return "gutter";
  if (a.sizes != b.sizes) return "sizes";
  for (int side = 0; side < 2; ++side) {
    const LookupAtlas &aa = a.atlases[side], &ab = b.atlases[side];
    if (aa.width != ab.width || aa.height != ab.height)
      return std::string("sides.") + (side == 0 ? "front" : "back") + ".size";
  }
  for (size_t i = 0; i < a.slots.size(); ++i)
    if (a.slots[i].x != b.slots[i].x || a.slots[i].y != b.slots[i].y) return "sides (squares)";
  return {};
}

void merge_tables(std::vector<LookupTable>& merged,
                  const std::vector<std::vector<LookupTable>>& parts) {
  for (size_t o = 0; o < merged.size(); ++o) {
    LookupTable& t = merged[o];
    std::fill(t.baked.begin(), t.baked.end(), 0);
    for (const auto& part : parts)
      for (size_t i = 0; i < t.baked.size(); ++i) t.baked[i] |= part[o].baked[i];
    t.allocate_atlases();
    const int nodes = t.node_count(), g = t.gutter;
    for (int q = 0; q < t.quad_count(); ++q)
      for (int n = 0; n < nodes; ++n)
        for (const auto& part : parts) {
          if (!part[o].is_baked(q, n)) continue;
          const int w = t.sizes[q] + 2 * g;
          for (int b = -g; b < t.sizes[q] + g; ++b)
            std::copy_n(part[o].texel(q, n, -g, b), size_t(w) * 4, t.texel(q, n, -g, b));
          break;
        }
  }
}

}  // namespace clothbake
