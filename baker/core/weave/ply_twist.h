#pragma once
/// Where a yarn's two twisted bundles lie about its axis (PAPER.md s.2, step
/// 2: the fibre tangent): a random phase per yarn of the weave repeat, plus
/// whole turns of the bundles per repeat, so the texture stays periodic.
///
/// One definition for the generator (which bundle a cell's fibres are in)
/// and for a material addressed per crossing, whose blocks can be keyed by
/// the phase at their crossing (CrossingClasses, docs/design/material.md, "The
/// per-pixel floor is the ply phase"): the phase is the one random draw of
/// the generator that shows per pixel at a thread per pixel or two.

#include <Imath/ImathVec.h>

#include "core/weave/cloth_spec.h"

namespace clothbake {

class PlyTwist {
 public:
  /// `weave_mm`: the weave's repeat (weave_repeat_mm: the draft as written,
  /// without its colour sequences), over which every random draw repeats.
  PlyTwist(const ClothSpec& spec, Imath::V2f weave_mm);

  /// The bundles' phase, radians (not wrapped), of warp end or weft pick
  /// `weave_yarn` (its index in the weave repeat) at `along_mm` along it
  /// (texture y for a warp end, x for a weft pick). Bundle 0 holds the
  /// polar angles in [phase, phase + pi) (mod 2 pi).
  float phase(bool warp, int weave_yarn, float along_mm) const;

 private:
  uint64_t m_seed;
  Imath::V2f m_weave_mm;
  float m_warp_turns, m_weft_turns;  // whole turns per weave repeat
};

}  // namespace clothbake
