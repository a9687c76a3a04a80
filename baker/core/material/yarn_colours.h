#pragma once
/// The yarn colours a colour-free material renders with
/// (docs/formats/material.md, "Colour-free parts"): per mip level, the warp
/// colour of every texel column and the weft colour of every texel row, over
/// the colours' own repeat (q material repeats when a per-thread colour
/// sequence does not divide the material's threads).
///
/// Which thread's colour: thread i owns the span between the midpoints to its
/// neighbours' centres; a level-0 column's colour is the length-weighted
/// average of the owners' colours over the column's span, and level m + 1 is
/// the pairwise average of level m's, so that every level is the exact box
/// average of level 0's colours.

#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/weave/cloth_spec.h"

namespace clothbake {

/// A cloth's colours: each family's colour and its per-thread sequence
/// (empty: every thread the family's colour), linear RGB.
struct YarnPalette {
  Imath::V3f warp_color{0.5f}, weft_color{0.5f};
  std::vector<Imath::V3f> warp_colors, weft_colors;
  bool operator==(const YarnPalette&) const = default;
};
YarnPalette palette_of(const ClothSpec& spec);

/// One family's strip: per level, q * (texels >> level) colours, those of
/// the threads owning each texel and those of their next neighbours on
/// either side (which a view ray reaches when it runs across the threads).
struct ColourStrip {
  int repeats = 1;  ///< q: material repeats per colour repeat
  std::vector<std::vector<Imath::V3f>> levels;  ///< the owning thread's colour
  std::vector<std::vector<Imath::V3f>> plus;    ///< the colour of the owner's thread + 1
  std::vector<std::vector<Imath::V3f>> minus;   ///< the colour of the owner's thread - 1
  /// Per thread of the q repeats, its own colour: what a material addressed
  /// per crossing reads (every texel of a block lies in one crossing).
  std::vector<Imath::V3f> threads;
};

/// The strip of threads with centres `centres_mm` (ascending, in [0,
/// repeat_mm): the material's repeat) coloured by `colours` in turn (a
/// sequence repeating; one colour for a plain family), for `texels` level-0
/// texels per repeat and `levels` levels.
ColourStrip colour_strip(std::span<const float> centres_mm, float repeat_mm,
                         std::span<const Imath::V3f> colours, int texels, int levels);

/// Each thread's centre over the colour-free cloth's repeat, warp ends along
/// x (warp = true) or weft picks along y.
std::vector<float> thread_centres_mm(const ClothSpec& colour_free_spec, bool warp);

/// The colour-free cloth's repeat along x (warp = true: the warp ends') or y.
float thread_repeat_mm(const ClothSpec& colour_free_spec, bool warp);

struct YarnColours {
  ColourStrip warp;  ///< along x: columns
  ColourStrip weft;  ///< along y: rows
};

/// The strips of `palette` on the colour-free cloth `colour_free_spec`.
YarnColours yarn_colours(const ClothSpec& colour_free_spec, const YarnPalette& palette,
                         int texels, int levels);

}  // namespace clothbake
