#pragma once
/// The depth at which a material's view nodes are aligned (view_parallax.h):
/// fitted once per material from its own tables, when it is baked or its
/// parts merged, as the depth at which neighbouring view nodes' images agree
/// best once shifted by parallax_shift_mm.

#include "core/material/cloth_material.h"

namespace clothbake {

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
