#pragma once
/// A cloth without its colours: what a colour-free material is baked from
/// (docs/material-format.md, "Colour-free parts"). The model is linear in the
/// yarn albedos, so the colours can be applied when the material renders; the
/// cloth that remains is the geometry, the density and the shading strengths.

#include "core/weave/cloth_spec.h"

namespace clothbake {

/// The albedo a colour-free cloth's yarns are generated with. The generator
/// clamps colour x diffuse scale to 1 and the scale is at most
/// max(diffuse_top, diffuse_bottom) x (1 + variation) <= 2, so 0.5 never clamps:
/// a cell's diffuse / k_neutral_albedo is its diffuse scale exactly.
inline constexpr float k_neutral_albedo = 0.5f;

/// `spec` with both families' colour the neutral grey and the per-thread
/// colour lists removed, so that its repeat is the draft's and the per-thread
/// spacings' and widths' alone; its resolution written out (cells_x, cells_y)
/// with the cell size the coloured cloth resolves to, rounded to whole cells
/// where the colour sequence's repeat does not divide it evenly.
ClothSpec colour_free(const ClothSpec& spec);

/// The extent of the weave's repeat without its colours (x along the weft, y
/// along the warp): the draft's and the per-thread spacings', a divisor of the
/// cloth's repeat when a colour sequence lengthens it.
Imath::V2f weave_repeat_mm(const ClothSpec& spec);

/// Whether two specs give the same colour-free cloth; when not, the first
/// field that differs (a cloth-spec path such as "warp.spacing_mm" or
/// "weave.draft") and the two values as text.
struct ClothDifference {
  std::string field;  ///< empty when the specs agree
  std::string a, b;
};
ClothDifference first_difference(const ClothSpec& a, const ClothSpec& b);

}  // namespace clothbake
