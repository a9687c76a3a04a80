#pragma once
/// Pictures of a volume texture for a person to read (pixels only; the I/O
/// layer writes them). All images are linear RGB, top row first.

#include "core/util/image.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

/// The weave seen from straight above, `repeats` x `repeats` tiles, each
/// `pixels_per_repeat` wide: cells composited front to back (opacity
/// 1 - exp(-sigma rho dz)) and shaded with Kajiya-Kay under a light from the
/// upper left, so fibre direction and the over/under pattern both show.
Image preview_top(const VolumeTexture& volume, int repeats, int pixels_per_repeat);

/// Vertical cross-section through the plane x = x_mm (along a warp yarn):
/// horizontal axis y over `repeats` repeats, vertical axis z (top face at the
/// top row), true aspect, `pixels_per_mm` pixels per millimetre. Each cell
/// shows its diffuse colour scaled by its density; empty cells are black.
Image preview_section_along_warp(const VolumeTexture& volume, float x_mm, int repeats,
                                 float pixels_per_mm);

/// As above through the plane y = y_mm (along a weft yarn); horizontal axis x.
Image preview_section_along_weft(const VolumeTexture& volume, float y_mm, int repeats,
                                 float pixels_per_mm);

/// Fibre tangents seen from above (top-most cell with rho > 0.05 in each
/// column), coloured as 0.5 + 0.5 v (x red, y green, z blue).
Image preview_tangents(const VolumeTexture& volume, int repeats, int pixels_per_repeat);

}  // namespace clothbake
