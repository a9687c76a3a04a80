#pragma once
/// A cloth without its colours: what a colour-free material is baked from
/// (docs/formats/material.md, "Colour-free parts"). The model is linear in the
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
/// colour lists removed, its draft cut to the drawdown's smallest repeat and
/// its per-thread spacings and widths to their smallest periods (a WIF writes
/// a plain weave over 214 ends to carry its colour stripes), so that its
/// repeat is the weave's alone; its resolution written out (cells_x, cells_y)
/// with the cell size the coloured cloth resolves to, rounded to whole cells
/// where the colour sequence's repeat does not divide it evenly. The
/// generator's per-thread randomness then repeats with the weave, as it
/// does for any cloth with a colour sequence.
ClothSpec colour_free(const ClothSpec& spec);

/// The extent of the weave's repeat without its colours (x along the weft, y
/// along the warp): the draft's as written and the per-thread spacings', a
/// divisor of the cloth's repeat when a colour sequence lengthens it. What a
/// scene's repeats_per_uv counts: a WIF's whole threading, a named pattern's
/// repeat, never a colour sequence.
Imath::V2f weave_repeat_mm(const ClothSpec& spec);

/// How many repeats of colour_free(spec) one weave_repeat_mm(spec) spans
/// along x and y (whole numbers: the colour-free repeat divides the written
/// one): 107 x 107 for a plain weave written over 214 x 214 threads, 1 x 1
/// for a draft written once. A reader that maps a mesh's UVs onto a
/// colour-free material by repeats_per_uv multiplies by it.
Imath::V2f colour_free_repeats(const ClothSpec& spec);

/// Whether two specs give the same colour-free cloth; when not, the first
/// field that differs (a cloth-spec path such as "warp.spacing_mm" or
/// "weave.draft") and the two values as text.
struct ClothDifference {
  std::string field;  ///< empty when the specs agree
  std::string a, b;
};
ClothDifference first_difference(const ClothSpec& a, const ClothSpec& b);

}  // namespace clothbake
