#pragma once
/// How many different places a weave repeat holds (docs/design/material.md,
/// "The weave's variety"): the distinct neighbourhoods of its crossings. A
/// material addressed per crossing would store one block of texels per
/// distinct neighbourhood instead of the whole repeat, so these counts say what
/// it would hold, against the repeat's crossings.
///
/// Colours never count (a colour-free material takes them at render time):
/// the repeat is the cloth's without its colours (colour_free), the draft's
/// smallest repeat (WeaveDraft::smallest_repeat) and the per-thread spacings'
/// and widths' smallest periods. A neighbourhood is a window of
/// the periodic drawdown around a crossing, with the spacing and the width of
/// each thread in the window:
///   plus 1       the crossing and the crossings either side of it along its
///                warp end and along its weft pick (what a yarn's path
///                through the crossing depends on), with the three ends and
///                the three picks through them;
///   square r     the (2r + 1) x (2r + 1) window (what a view or shadow ray
///                that crosses r threads sees).

#include <array>
#include <vector>

#include "core/weave/cloth_spec.h"

namespace clothbake {

struct NeighbourhoodCounts {
  int ends = 0;                 ///< warp ends of the colour-free repeat
  int picks = 0;                ///< weft picks of it
  int plus1 = 0;                ///< distinct plus-shaped stencils of radius 1
  std::array<int, 3> square{};  ///< distinct square windows of radius 1, 2, 3
  long long crossings() const { return (long long)ends * picks; }
};

/// Every crossing of a colour-free cloth sorted into its plus-1 class (the
/// blocks of a material addressed per crossing, docs/formats/material.md,
/// "Addressed per crossing"): classes numbered in order of first appearance
/// (pick-major), each with the first crossing of it as its representative.
struct CrossingClasses {
  int ends = 0, picks = 0;
  std::vector<int> class_of;  ///< [pick * ends + end]
  struct Crossing {
    int end = 0, pick = 0;
  };
  std::vector<Crossing> representative;  ///< per class
  int count() const { return int(representative.size()); }
  /// Up to `n` crossings of class b: its representative, then the others
  /// spread evenly over them in pick-major order.
  std::vector<Crossing> members(int b, int n) const;
  int at(int end, int pick) const {
    const int e = ((end % ends) + ends) % ends, p = ((pick % picks) + picks) % picks;
    return class_of[size_t(p) * size_t(ends) + size_t(e)];
  }
};

/// What makes two crossings one class: the plus-1 stencil, or the square
/// window of radius 1 (3 x 3 crossings: the neighbouring ends' and picks'
/// crossings too, which grazing view and shadow rays reach).
enum class CrossingStencil { Plus1, Square1 };

/// The classes of `colour_free_spec` (already colour_free(): its threads are
/// the material's) by `stencil`, over its thread layouts' repeat. With
/// `phase_bins` > 1 a class also holds one bin of the ply phase (PlyTwist)
/// of the yarn on top at the crossing's centre, the phase cut into that many
/// equal bins: the one random draw that shows per pixel at a thread per pixel
/// or two (docs/design/material.md, "The per-pixel floor is the ply phase"); the
/// representative is then the class's crossing nearest its bin's centre.
CrossingClasses crossing_classes(const ClothSpec& colour_free_spec,
                                 CrossingStencil stencil = CrossingStencil::Plus1,
                                 int phase_bins = 1);

/// The counts of `spec`'s weave (deterministic; about a second for a 641 x 641
/// repeat).
NeighbourhoodCounts crossing_neighbourhoods(const ClothSpec& spec);

}  // namespace clothbake
