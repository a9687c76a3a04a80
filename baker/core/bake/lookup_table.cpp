#include "core/bake/lookup_table.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace clothbake {

bool LookupTable::quad_baked(int quad) const {
  for (int n = 0; n < node_count(); ++n)
    if (is_baked(quad, n)) return true;
  return false;
}

void LookupTable::pack(const std::vector<uint8_t>& wanted) {
  const int nodes = node_count(), g = gutter;
  slots.assign(size_t(quad_count()) * nodes, SquareSlot{});
  for (int side = 0; side < 2; ++side) {
    // (size, quad, node) of every square of this side, largest first.
    std::vector<std::tuple<int, int, int>> squares;
    double area = 0.0;
    for (int q = 0; q < quad_count(); ++q) {
      if (sizes[q] <= 0) continue;
      for (int n = side * dirs.nodes_per_side(); n < (side + 1) * dirs.nodes_per_side(); ++n)
        if (wanted[size_t(q) * nodes + n]) {
          squares.emplace_back(sizes[q], q, n);
          area += double(sizes[q] + 2 * g) * (sizes[q] + 2 * g);
        }
    }
    LookupAtlas& atlas = atlases[side];
    atlas = LookupAtlas{};
    if (squares.empty()) continue;
    std::stable_sort(squares.begin(), squares.end(),
                     [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
    const int largest = std::get<0>(squares.front()) + 2 * g;
    // Rows about as wide as the square root of the total area: a roughly
    // square image, which image tools and GPUs handle best.
    const int width = std::max(largest, int(std::ceil(std::sqrt(area) * 1.05)));
    int x = 0, y = 0, row_height = 0;
    for (const auto& [size, q, n] : squares) {
      const int w = size + 2 * g;
      if (x + w > width) {
        x = 0;
        y += row_height;
        row_height = 0;
      }
      slots[size_t(q) * nodes + n] = SquareSlot{x + g, y + g};
      x += w;
      row_height = std::max(row_height, w);
    }
    atlas.width = width;
    atlas.height = y + row_height;
  }
}

void LookupTable::allocate_atlases() {
  for (LookupAtlas& a : atlases)
    a.pixels.assign(size_t(a.width) * size_t(a.height) * 4, Imath::half(0.0f));
}

Imath::half* LookupTable::texel(int quad, int node, int a, int b) {
  const SquareSlot& s = slot(quad, node);
  LookupAtlas& atlas = atlases[side_of(node)];
  return &atlas.pixels[(size_t(s.y + b) * atlas.width + size_t(s.x + a)) * 4];
}

const Imath::half* LookupTable::texel(int quad, int node, int a, int b) const {
  const SquareSlot& s = slot(quad, node);
  const LookupAtlas& atlas = atlases[side_of(node)];
  return &atlas.pixels[(size_t(s.y + b) * atlas.width + size_t(s.x + a)) * 4];
}

bool LookupTable::sample(int quad, float s, float t, const Imath::V3f& to_eye_local,
                         float rgba[4]) const {
  const int size = sizes[quad];
  if (size == 0) return false;
  // Texel-centre coordinates inside the square, clamped so that bilinear
  // filtering never reads outside it.
  const float cx = std::clamp(s * size - 0.5f, 0.0f, float(size - 1));
  const float cy = std::clamp((1.0f - t) * size - 0.5f, 0.0f, float(size - 1));
  const int a0 = std::min(int(cx), size - 1), b0 = std::min(int(cy), size - 1);
  const int a1 = std::min(a0 + 1, size - 1), b1 = std::min(b0 + 1, size - 1);
  const float fa = cx - float(a0), fb = cy - float(b0);

  const DirectionGrid::Footprint f = dirs.locate(to_eye_local);
  const int nodes[4] = {dirs.node_index(f.side, f.i0, f.j0), dirs.node_index(f.side, f.i1, f.j0),
                        dirs.node_index(f.side, f.i0, f.j1), dirs.node_index(f.side, f.i1, f.j1)};
  const float wn[4] = {(1 - f.fx) * (1 - f.fy), f.fx * (1 - f.fy), (1 - f.fx) * f.fy, f.fx * f.fy};
  for (int c = 0; c < 4; ++c) rgba[c] = 0.0f;
  for (int n = 0; n < 4; ++n) {
    if (wn[n] == 0.0f) continue;
    if (!is_baked(quad, nodes[n])) return false;
    const Imath::half* t00 = texel(quad, nodes[n], a0, b0);
    const Imath::half* t10 = texel(quad, nodes[n], a1, b0);
    const Imath::half* t01 = texel(quad, nodes[n], a0, b1);
    const Imath::half* t11 = texel(quad, nodes[n], a1, b1);
    for (int c = 0; c < 4; ++c) {
      const float v = (float(t00[c]) * (1 - fa) + float(t10[c]) * fa) * (1 - fb) +
                      (float(t01[c]) * (1 - fa) + float(t11[c]) * fa) * fb;
      rgba[c] += wn[n] * v;
    }
  }
  return true;
}

void LookupTable::fill_gutters() {
  for (int q = 0; q < quad_count(); ++q) {
    const int size = sizes[q];
    if (size == 0) continue;
    for (int node = 0; node < node_count(); ++node) {
      if (!is_baked(q, node) || !slot(q, node).valid()) continue;
      for (int b = -gutter; b < size + gutter; ++b)
        for (int a = -gutter; a < size + gutter; ++a) {
          if (a >= 0 && a < size && b >= 0 && b < size) continue;
          const Imath::half* from =
              texel(q, node, std::clamp(a, 0, size - 1), std::clamp(b, 0, size - 1));
          std::copy_n(from, 4, texel(q, node, a, b));
        }
    }
  }
}

uint64_t LookupTable::atlas_bytes() const {
  uint64_t bytes = 0;
  for (const LookupAtlas& a : atlases) bytes += uint64_t(a.width) * uint64_t(a.height) * 4 * 2;
  return bytes;
}

}  // namespace clothbake
