#include "core/lookup_table.h"

#include <algorithm>
#include <cmath>

namespace clothbake {

void LookupTable::allocate_tiles() {
  tiles.assign(size_t(node_count()), {});
  for (int node = 0; node < node_count(); ++node)
    for (size_t q = 0; q < rects.size(); ++q)
      if (is_baked(int(q), node)) {
        tiles[node].assign(size_t(tile_width) * tile_height * 4, Imath::half(0.0f));
        break;
      }
}

bool LookupTable::sample(int quad, float s, float t, const Imath::V3f& to_eye_local,
                         float rgba[4]) const {
  const QuadRect& r = rects[quad];
  if (r.size == 0) return false;
  // Texel-centre coordinates inside the square, clamped so that bilinear
  // filtering never reads outside it.
  const float cx = std::clamp(s * r.size - 0.5f, 0.0f, float(r.size - 1));
  const float cy = std::clamp((1.0f - t) * r.size - 0.5f, 0.0f, float(r.size - 1));
  const int a0 = std::min(int(cx), r.size - 1), b0 = std::min(int(cy), r.size - 1);
  const int a1 = std::min(a0 + 1, r.size - 1), b1 = std::min(b0 + 1, r.size - 1);
  const float fa = cx - float(a0), fb = cy - float(b0);

  const DirectionGrid::Footprint f = dirs.locate(to_eye_local);
  const int nodes[4] = {dirs.node_index(f.side, f.i0, f.j0), dirs.node_index(f.side, f.i1, f.j0),
                        dirs.node_index(f.side, f.i0, f.j1), dirs.node_index(f.side, f.i1, f.j1)};
  const float wn[4] = {(1 - f.fx) * (1 - f.fy), f.fx * (1 - f.fy), (1 - f.fx) * f.fy, f.fx * f.fy};
  for (int c = 0; c < 4; ++c) rgba[c] = 0.0f;
  for (int n = 0; n < 4; ++n) {
    if (wn[n] == 0.0f) continue;
    if (!is_baked(quad, nodes[n])) return false;
    const std::vector<Imath::half>& tile = tiles[nodes[n]];
    auto texel = [&](int a, int b, int c) {
      return float(tile[((size_t(r.y + b) * tile_width) + r.x + a) * 4 + c]);
    };
    for (int c = 0; c < 4; ++c) {
      const float v = (texel(a0, b0, c) * (1 - fa) + texel(a1, b0, c) * fa) * (1 - fb) +
                      (texel(a0, b1, c) * (1 - fa) + texel(a1, b1, c) * fa) * fb;
      rgba[c] += wn[n] * v;
    }
  }
  return true;
}

bool LookupTable::quad_baked(int quad) const {
  for (int n = 0; n < node_count(); ++n)
    if (is_baked(quad, n)) return true;
  return false;
}

void LookupTable::fill_gutters() {
  for (int node = 0; node < node_count(); ++node) {
    std::vector<Imath::half>& tile = tiles[node];
    if (tile.empty()) continue;
    for (size_t q = 0; q < rects.size(); ++q) {
      const QuadRect& r = rects[q];
      if (r.size == 0 || !is_baked(int(q), node)) continue;
      for (int b = -gutter; b < r.size + gutter; ++b)
        for (int a = -gutter; a < r.size + gutter; ++a) {
          if (a >= 0 && a < r.size && b >= 0 && b < r.size) continue;
          const int sa = std::clamp(a, 0, r.size - 1), sb = std::clamp(b, 0, r.size - 1);
          const int x = r.x + a, y = r.y + b;
          if (x < 0 || y < 0 || x >= tile_width || y >= tile_height) continue;
          for (int c = 0; c < 4; ++c)
            tile[(size_t(y) * tile_width + x) * 4 + c] =
                tile[(size_t(r.y + sb) * tile_width + r.x + sa) * 4 + c];
        }
    }
  }
}

}  // namespace clothbake
