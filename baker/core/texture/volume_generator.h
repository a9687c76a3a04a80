#pragma once
/// Generates the woven cloth's volume texture from a ClothSpec (PAPER.md s.2).
///
/// Yarn model: each warp end / weft pick is an elliptical cross-section
/// (width x thickness) swept along a path that goes over and under the other
/// family as the draft says, blended by half a cosine between crossings. Each
/// yarn is two fibre bundles twisted round each other (the paper's Figure 1):
/// the boundary between the bundles turns once per ply pitch along the yarn,
/// and the fibres of one bundle run at +twist, those of the other at -twist to
/// the yarn axis; these are the paper's base vectors v_V and v_H, which are then
/// perturbed by a seeded random rotation. rho is the cell's occupied fraction
/// (s^3 sub-cell points), denser at a yarn's centre and deep in the cloth.

#include <cstdint>

#include "core/weave/cloth_spec.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

/// Derived geometry of a spec: sizes of the repeat and the yarn paths.
struct WeaveGeometry {
  Imath::V3f size_mm;      ///< repeat extent x, y and cloth thickness z
  float amplitude_mm = 0;  ///< over/under amplitude of the yarn centre lines
  float z_mid_mm = 0;      ///< height of the mid-plane the yarns undulate about
};
WeaveGeometry weave_geometry(const ClothSpec& spec);

/// Bytes the generator will allocate for `spec` (the grid plus working memory).
uint64_t estimated_volume_bytes(const ClothSpec& spec);

/// Validates `spec`, refuses (InputError naming "resolution", with the
/// estimate) a grid over `memory_budget_bytes`, then generates the grid.
/// Deterministic: equal spec gives equal bytes for any thread count.
VolumeTexture generate_volume(const ClothSpec& spec, uint64_t memory_budget_bytes);

}  // namespace clothbake
