#pragma once
/// Parallax-aligned view interpolation: where a lookup reads each view node
/// (docs/design/material.md, "View nodes and parallax").
///
/// A view ray that enters the slab at x is, at depth h below the top face,
/// at x - h * slope(to_eye) (slope = (x, y) / z in texture space). Two
/// neighbouring view nodes of a thick cloth therefore show the weave shifted
/// against each other by h * (slope difference), several threads near the
/// horizon; blending them at the same x blurs the weave. shade() instead
/// reads each view node where its ray meets the eye ray's at one depth h:
///   x_node = x + parallax_shift_mm(to_eye, node),
/// which is x itself when the eye sits on the node, so the nodes stay exact.
/// h is fitted once per material, when it is baked (material_bake/parallax_fit.h).

#include <Imath/ImathVec.h>

namespace clothbake {

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

}  // namespace clothbake
