#pragma once
/// A baked view-dependent lookup of one cloth object (docs/formats/lookup.md):
/// for each baked (quad, direction node) pair, a square of texels over the
/// quad's patch parameters (s, t) holding the RGBA seen from that direction:
/// RGB the radiance leaving toward it (premultiplied: it already includes the
/// cloth's coverage), A the opacity 1 - see-through.
///
/// Storage is packed: each side (front, back) has one atlas, and only the
/// pairs a bake needs get a square there (plus a gutter of copies of its
/// edge texels), so an adaptive bake that needs a few hundred of the
/// quads x 2K^2 pairs stores only those. Texel (a, b) of a square (column a,
/// row b from the top) is centred at s = (a + 0.5) / size,
/// t = 1 - (b + 0.5) / size.

#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>
#include <Imath/half.h>

#include "core/geometry/direction_grid.h"

namespace clothbake {

/// Where a (quad, node) square sits in its side's atlas: the top-left texel
/// inside the gutter. x < 0: the pair has no square.
struct SquareSlot {
  int x = -1, y = -1;
  bool valid() const { return x >= 0; }
};

/// One side's atlas: width x height RGBA halves, rows from the top.
struct LookupAtlas {
  int width = 0, height = 0;
  std::vector<Imath::half> pixels;
};

class LookupTable {
 public:
  DirectionGrid dirs;
  int gutter = 1;                 ///< texels of edge copies around each square
  std::vector<int> sizes;         ///< per quad: texels per side of its squares; 0 = none
  std::vector<uint8_t> baked;     ///< per quad x node (quad * 2K^2 + node): 1 = holds values
  std::vector<SquareSlot> slots;  ///< per quad x node: its square, if it has one
  LookupAtlas atlases[2];         ///< front (side 0) and back (side 1)

  int quad_count() const { return int(sizes.size()); }
  int node_count() const { return 2 * dirs.nodes_per_side(); }
  int side_of(int node) const { return node / dirs.nodes_per_side(); }
  bool is_baked(int quad, int node) const { return baked[size_t(quad) * node_count() + node] != 0; }
  const SquareSlot& slot(int quad, int node) const {
    return slots[size_t(quad) * node_count() + node];
  }
  /// True if the quad has any baked node.
  bool quad_baked(int quad) const;

  /// Gives every (quad, node) with `wanted` set (same indexing as `baked`)
  /// and a non-zero size a square in its side's atlas and sizes the
  /// atlases (pixels left empty). Shelf packing, largest squares first, ties
  /// in (quad, node) order: deterministic, a function of sizes and wanted
  /// only, so partial bakes of one scene share the layout.
  void pack(const std::vector<uint8_t>& wanted);
  /// Allocates both atlases' pixels (zeros).
  void allocate_atlases();

  /// Texel (a, b) of the (quad, node) square; a, b in [-gutter, size + gutter).
  Imath::half* texel(int quad, int node, int a, int b);
  const Imath::half* texel(int quad, int node, int a, int b) const;

  /// RGBA seen at (s, t) of `quad` from `to_eye_local` (local frame):
  /// bilinear between texel centres (clamped inside the square), then
  /// bilinear between the four direction nodes. False if the quad or one of
  /// the four nodes (with non-zero weight) was not baked.
  bool sample(int quad, float s, float t, const Imath::V3f& to_eye_local, float rgba[4]) const;

  /// Fills each baked square's gutter with copies of its edge texels.
  void fill_gutters();

  /// Bytes of both atlases as stored (half RGBA), whether allocated or not.
  uint64_t atlas_bytes() const;
};

}  // namespace clothbake
