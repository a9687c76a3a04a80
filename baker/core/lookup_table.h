#pragma once
/// A baked view-dependent lookup of one cloth object (docs/lookup-format.md):
/// for each baked quad, a square of texels over its patch parameters (s, t);
/// for each baked direction node, the RGBA seen at every texel: RGB the
/// radiance leaving toward that direction (premultiplied: it already includes
/// the cloth's coverage), A the opacity 1 - see-through.
///
/// Texel layout: quad q owns the square rects[q] (size x size texels, plus a
/// gutter of copies of its edge texels around it) in every direction tile;
/// texel (a, b) of the square (column a, row b from the top) is centred at
/// s = (a + 0.5) / size, t = 1 - (b + 0.5) / size.

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>
#include <Imath/half.h>

#include "core/direction_grid.h"

namespace clothbake {

struct QuadRect {
  int x = 0, y = 0;  ///< top-left texel of the square (inside the gutter)
  int size = 0;      ///< texels per side; 0 = the quad is not baked
};

class LookupTable {
 public:
  DirectionGrid dirs;
  int tile_width = 0, tile_height = 0;  ///< texels of one direction tile
  int gutter = 1;                       ///< texels of edge copies around each square
  std::vector<QuadRect> rects;          ///< per quad
  std::vector<uint8_t> baked;           ///< per quad x node (quad * 2k^2 + node): 1 = baked
  /// Per node: tile_width x tile_height x 4 halves, rows from the top; empty
  /// when no quad bakes that node.
  std::vector<std::vector<Imath::half>> tiles;

  int node_count() const { return 2 * dirs.nodes_per_side(); }
  bool is_baked(int quad, int node) const { return baked[size_t(quad) * node_count() + node] != 0; }
  /// Allocates `tiles` for every node some quad bakes (zeros elsewhere).
  void allocate_tiles();

  /// RGBA seen at (s, t) of `quad` from `to_eye_local` (local frame):
  /// bilinear between texel centres (clamped inside the quad's square), then
  /// bilinear between the four direction nodes. False if the quad or one of
  /// the four nodes was not baked.
  bool sample(int quad, float s, float t, const Imath::V3f& to_eye_local, float rgba[4]) const;

  /// Fills each baked square's gutter with copies of its edge texels.
  void fill_gutters();
  /// True if the quad has any baked node.
  bool quad_baked(int quad) const;
};

}  // namespace clothbake
