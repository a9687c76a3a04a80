#pragma once
/// Parallax-aligned view interpolation (issue 22, item 4; docs/material.md,
/// "View nodes and parallax").
///
/// A view ray that enters the slab at x is, at depth h below the top face,
/// at x - h * slope(to_eye) (slope = (x, y) / z in texture space). Two
/// neighbouring view nodes of a thick cloth therefore show the weave shifted
/// against each other by h * (slope difference), several threads near the
/// horizon; blending them at the same x blurs the weave. shade() instead
/// reads each view node where its ray meets the eye ray's at one depth h:
///   x_node = x + parallax_shift_mm(to_eye, node),
/// which is x itself when the eye sits on the node, so the nodes stay exact.
/// h is fitted once per material from its own tables (fit_view_parallax):
/// the depth at which neighbouring view nodes' images agree best.

#include <Imath/ImathVec.h>

namespace clothbake {

class ClothMaterial;

/// sin(1 degree): the bake's horizon clamp (DirectionGrid::bake_direction),
/// used for slopes too, so that a slope is always finite.
inline constexpr float k_parallax_min_z = 0.0174524f;

/// (x, y) / max(|z|, sin 1 deg) of a material-frame direction: the slope in
/// the material frame (texture slope = this / depth_scale).
Imath::V2f material_slope(const Imath::V3f& d_material);

/// Where (texture mm, added to x) the view node of material-frame direction
/// `node_material` is read for the eye direction `to_eye_material`, with
/// the material's fitted depth `depth_mm` and depth scale. Zero at depth 0.
Imath::V2f parallax_shift_mm(const Imath::V3f& to_eye_material, const Imath::V3f& node_material,
                             float depth_mm, float depth_scale);

/// What fit_view_parallax found: the depth and how much better it aligns.
struct ViewParallaxFit {
  float depth_mm = 0.0f;
  float mismatch_at_zero = 0.0f;  ///< mean relative squared difference of neighbours, h = 0
  float mismatch = 0.0f;          ///< the same at depth_mm
};

/// The depth h in [0, thickness / 2] (41 steps) at which neighbouring view
/// nodes (same side, both within 70 degrees of the normal: nearer the
/// horizon a neighbour is another image, which no shift aligns), read at
/// level 0 under light from every light node at once, differ least once
/// shifted by parallax_shift_mm. Deterministic and serial (about 10^7
/// bilinear taps).
ViewParallaxFit fit_view_parallax(const ClothMaterial& material);

}  // namespace clothbake
