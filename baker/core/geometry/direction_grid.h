#pragma once
/// View directions of a baked lookup: a K x K grid over each hemisphere of
/// the local frame (T, B, N), on the hemi-octahedral map.
///
/// A direction d (unit, pointing from the surface toward the eye) with
/// d.z >= 0 is seen on the front side; d.z < 0 on the back side, which uses
/// the same map with z mirrored. The map: p = (d.x, d.y) / (|d.x| + |d.y| + |d.z|)
/// lies in the diamond |p.x| + |p.y| <= 1; rotating it by 45 degrees,
/// (u, v) = ((p.x + p.y + 1) / 2, (p.x - p.y + 1) / 2), fills the unit square,
/// whose boundary is the horizon. Nodes sit at i / (K - 1) (corners and
/// horizon included), so every direction interpolates bilinearly between four
/// nodes of one side, with no extrapolation. Why hemi-octahedral:
/// docs/formats/lookup.md (node spacing and measured error at grazing angles).

#include <Imath/ImathVec.h>

namespace clothbake {

/// (u, v) in [0, 1]^2 of a direction of the upper hemisphere (z >= 0; a
/// negative z is taken as its mirror).
Imath::V2f hemi_oct_encode(const Imath::V3f& d);
/// Unit direction (z >= 0) of (u, v) in [0, 1]^2.
Imath::V3f hemi_oct_decode(const Imath::V2f& uv);

/// How a hemisphere's K x K nodes are laid out.
enum class DirectionMap {
  /// The hemi-octahedral square above; nodes at (i, j) / (K - 1).
  HemiOctahedral,
  /// Polar: node (i, j) at azimuth phi = 2 pi i / K (periodic in i) and
  /// polar angle theta = (pi / 2) j / (K - 1) from the normal (j = 0: the
  /// normal, every i the same direction; j = K - 1: the horizon).
  Polar,
  /// The hemi-octahedral square with its nodes drawn toward the horizon:
  /// the diamond's radius rho = |p.x| + |p.y| (1 on the horizon) is mapped
  /// to rho' = 1 - sqrt(1 - rho) before the square's grid is laid, so node
  /// rows are twice as dense at the horizon and half as dense at the normal.
  /// The light nodes of a cloth material (grazing light changes fastest).
  HemiOctahedralHorizon
};

struct DirectionGrid {
  int k = 8;  ///< nodes per side of each hemisphere's square, >= 2
  DirectionMap map = DirectionMap::HemiOctahedral;

  int nodes_per_side() const { return k * k; }
  /// Index of node (side, i, j): side * k * k + j * k + i.
  int node_index(int side, int i, int j) const { return (side * k + j) * k + i; }
  /// Unit direction of a node (toward the eye, local frame).
  Imath::V3f node_direction(int side, int i, int j) const;
  /// The same for a node index.
  Imath::V3f node_direction(int node) const {
    const int rem = node % nodes_per_side();
    return node_direction(node / nodes_per_side(), rem % k, rem / k);
  }

  /// The direction a node is baked from: its own, except on the horizon,
  /// where a ray parallel to the surface never enters the volume; there the
  /// node holds the limit toward the horizon, taken at 1 degree of elevation
  /// on the node's side.
  Imath::V3f bake_direction(int side, int i, int j) const;
  /// The same for a node index.
  Imath::V3f bake_direction(int node) const {
    const int rem = node % nodes_per_side();
    return bake_direction(node / nodes_per_side(), rem % k, rem / k);
  }

  /// The four nodes a direction is interpolated from, and the weights.
  /// A non-finite direction is read as the normal (0, 0, 1).
  struct Footprint {
    int side = 0;
    int i0 = 0, i1 = 0, j0 = 0, j1 = 0;  ///< the four nodes are (i0|i1, j0|j1)
    float fx = 0.0f, fy = 0.0f;          ///< weights of i1 and j1
  };
  Footprint locate(const Imath::V3f& to_eye_local) const;
};

}  // namespace clothbake
