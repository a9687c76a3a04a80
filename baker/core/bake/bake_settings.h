#pragma once
/// What a bake is asked to compute, and the ranges each setting may take.
/// The ranges are stated here once: the core checks them (plan_bake), the
/// manifest reader (io/lookup_manifest) and the command line (cli/cmd_bake)
/// use them, and the add-on's tests read them from this file
/// (tests/addon/test_defaults.py).

#include <cstdint>

#include "core/geometry/direction_grid.h"

namespace clothbake {

inline constexpr int k_min_directions = 2, k_max_directions = 64;  ///< K
inline constexpr int k_min_texels = 1, k_max_texels = 4096;        ///< R, texels per quad side
inline constexpr int k_min_bake_spp = 1, k_max_bake_spp = 4096;    ///< samples per texel
inline constexpr float k_max_texels_per_pixel = 64.0f;             ///< adaptive, in (0, this]

struct BakeSettings {
  int directions = 8;  ///< K: direction nodes per side of each hemisphere, [2, 64]
  DirectionMap map = DirectionMap::HemiOctahedral;  ///< node layout (docs/formats/lookup.md)
  int texels = 64;                ///< texels per quad side in a full bake, [1, 4096]
  int spp = 4;                    ///< jittered sub-texel samples per texel and direction
  bool adaptive = false;          ///< derive quads, texels and directions from the camera
  float texels_per_pixel = 1.5f;  ///< adaptive: texels per projected pixel along a quad edge
  int min_texels = 4, max_texels = 1024;  ///< adaptive: bounds on texels per quad side
  int quad_begin = 0, quad_end = -1;      ///< bake quads [begin, end) only (-1: to the last)
  /// Of those, quads q with q mod shard_count == shard_index only: part
  /// shard_index + 1 of shard_count (--shard I/N). Every part shares the
  /// whole bake's layout, so the parts merge into it (lookup_merge.h);
  /// dealing quads in turn spreads the camera's near and far ones.
  int shard_index = 0, shard_count = 1;
  uint64_t seed = 1;
};

}  // namespace clothbake
