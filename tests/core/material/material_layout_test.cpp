// The material's shape stated once (core/material/material_layout.h): the
// byte counts are those of the arrays ClothMaterial really allocates, and
// every texel of every view node has its own atlas pixel.

#include <set>

#include <gtest/gtest.h>

#include "core/material/cloth_material.h"
#include "core/material/material_layout.h"

namespace clothbake {
namespace {

TEST(MaterialLayout, LevelsAndNodeCounts) {
  MaterialLayout l{1, 2, 3};
  EXPECT_EQ(l.levels(), 1);
  EXPECT_EQ(l.view_count(), 8);
  EXPECT_EQ(l.light_count(), 18);
  l.texels = 32;
  EXPECT_EQ(l.levels(), 6);  // 32, 16, 8, 4, 2, 1
  EXPECT_EQ(l.level_side(5), 1);
  EXPECT_EQ(l.pyramid_texels(), 1024u + 256 + 64 + 16 + 4 + 1);
}

// table_bytes(rank) is what allocate() takes: every level's coefficients
// and alpha, and the light factors.
TEST(MaterialLayout, TableBytesAreTheAllocatedBytes) {
  for (int rank : {0, 1, 5}) {
    ClothMaterial m;
    m.settings.texels = 8;
    m.settings.directions = 3;
    m.settings.light_directions = 2;
    m.view_grid.k = 3;
    m.light_grid.k = 2;
    m.max_rank = rank;
    m.allocate();
    uint64_t bytes = m.light_factors.size() * sizeof(float);
    for (int l = 0; l < m.levels(); ++l)
      bytes += m.coefficients[l].size() * sizeof(Imath::V3f) + m.alpha[l].size() * sizeof(float);
    EXPECT_EQ(m.layout().table_bytes(rank), bytes) << "rank " << rank;
    EXPECT_EQ(m.levels(), m.layout().levels());
  }
}

TEST(MaterialLayout, AtlasPixelsAreABijection) {
  const MaterialLayout l{8, 3, 2};
  for (int level = 0; level < l.levels(); ++level) {
    std::set<size_t> seen;
    const int side = l.level_side(level);
    for (int v = 0; v < l.view_count(); ++v)
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) seen.insert(l.atlas_pixel(v, x, y, level));
    EXPECT_EQ(seen.size(), size_t(l.atlas_width(level)) * size_t(l.atlas_height(level)));
    EXPECT_EQ(*seen.rbegin(), seen.size() - 1);
  }
}

}  // namespace
}  // namespace clothbake
