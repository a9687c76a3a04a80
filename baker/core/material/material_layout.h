#pragma once
/// The shape of a cloth material's table, stated once (docs/formats/material.md):
/// how many view and light nodes, how many mip levels of how many texels, where
/// a texel sits in a level's atlas image, and how many bytes the table takes at
/// a given rank, in memory, in its files and while it is baked. The bake, its
/// probe, the folder's writer and reader, and the estimate all read it here.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/material/material_settings.h"

namespace clothbake {

struct MaterialLayout {
  int texels = 32;            ///< R: texels per repeat side at level 0, a power of 2
  int directions = 16;        ///< K: view nodes per side of each hemisphere's grid
  int light_directions = 10;  ///< KL: light nodes per side of each hemisphere's grid
  /// Values per coefficient slot: RGB, or the colour-free parts (specular,
  /// own warp, own weft, next warp, next weft: docs/formats/material.md).
  int channels = 3;
  /// 0: the texels cover the whole repeat (R x R). Otherwise a material
  /// addressed per crossing: `blocks` blocks of R x R texels, one per
  /// crossing class, stacked in a column (block b's rows b R .. b R + R - 1),
  /// so that a 2 x 2 box average of a level's image is the box average inside
  /// each block and never mixes two.
  int blocks = 0;

  static MaterialLayout of(const MaterialSettings& s, int blocks = 0) {
    return MaterialLayout{s.texels, s.directions, s.light_directions,
                          s.parts == MaterialParts::SpecularWarpWeft ? 5 : 3,
                          s.address == MaterialAddress::Crossings ? blocks : 0};
  }

  /// Two hemispheres of K x K (KL x KL) nodes (direction_grid.h).
  int view_count() const { return 2 * directions * directions; }
  int light_count() const { return 2 * light_directions * light_directions; }

  /// Level m + 1 halves level m, down to 1 x 1: log2(R) + 1 levels.
  int levels() const {
    int n = 1;
    while ((texels >> (n - 1)) > 1) ++n;
    return n;
  }
  /// A level's texels per row (per repeat, or per crossing when addressed).
  int level_side(int level) const { return std::max(1, texels >> level); }
  /// A level's rows: its side, or its blocks' sides stacked.
  int level_rows(int level) const { return level_side(level) * std::max(1, blocks); }
  size_t level_texels(int level) const { return size_t(level_side(level)) * level_rows(level); }
  /// Texels of one view node over every level (about 4/3 R^2).
  uint64_t pyramid_texels() const {
    uint64_t n = 0;
    for (int m = 0; m < levels(); ++m) n += level_texels(m);
    return n;
  }

  /// A level's atlas image: view node v's tile of side x rows texels at
  /// column v % K, row v / K (K tiles a row, 2 K rows).
  int atlas_width(int level) const { return directions * level_side(level); }
  int atlas_height(int level) const { return 2 * directions * level_rows(level); }
  size_t atlas_pixel(int view, int x, int y, int level) const {
    const size_t side = size_t(level_side(level));
    const size_t px = size_t(view % directions) * side + size_t(x);
    const size_t py = size_t(view / directions) * size_t(level_rows(level)) + size_t(y);
    return py * size_t(directions) * side + px;
  }

  /// The table in memory at `rank` coefficient slots: per view node and
  /// texel of every level `channels` floats per slot and an alpha, and the float
  /// light factors (nodes x rank per view node).
  uint64_t table_bytes(int rank) const {
    const uint64_t r = uint64_t(std::max(rank, 0));
    return uint64_t(view_count()) *
           (pyramid_texels() * (uint64_t(channels) * r + 1) + uint64_t(light_count()) * r) * sizeof(float);
  }
  /// The folder's images uncompressed at `rank` coefficient slots (a mean
  /// rank may be fractional): half coefficients and alpha per level, float
  /// light factors (at least one channel).
  uint64_t file_bytes(double rank) const {
    const double r = std::max(rank, 0.0);
    return uint64_t(double(view_count()) *
                    (double(pyramid_texels()) * (1.0 + double(channels) * r) * 2.0 +
                     double(light_count()) * std::max(1.0, r) * 4.0));
  }
  /// What one bake worker holds for the view node it marches: the texels x
  /// RGB by light-node matrix and its factorised copy.
  uint64_t view_matrix_bytes() const {
    return level_texels(0) * uint64_t(channels) * uint64_t(light_count()) * sizeof(float) * 2;
  }
};

}  // namespace clothbake
