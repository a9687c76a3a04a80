// The distinct neighbourhoods of a weave's crossings (core/weave/
// crossing_neighbourhoods.h): the counts of named weaves, known by hand, and
// what changes them (spacings) and what does not (colours).

#include "core/weave/crossing_neighbourhoods.h"

#include <cmath>
#include <cstdint>
#include <numbers>

#include <gtest/gtest.h>

#include "core/weave/cloth_colours.h"
#include "core/weave/ply_twist.h"
#include "core/weave/thread_layout.h"

namespace clothbake {
namespace {

ClothSpec named(const char* pattern) {
  ClothSpec s;
  s.pattern = pattern;
  return s;
}

TEST(CrossingNeighbourhoods, PlainWeaveHoldsTwo) {
  // Every window of a plain weave is set by its centre: warp or weft up.
  const NeighbourhoodCounts n = crossing_neighbourhoods(named("plain"));
  EXPECT_EQ(n.ends, 2);
  EXPECT_EQ(n.picks, 2);
  EXPECT_EQ(n.plus1, 2);
  for (int c : n.square) EXPECT_EQ(c, 2);
}

TEST(CrossingNeighbourhoods, TwillHoldsItsFourPlacesInTheFloat) {
  // 2/2 twill: each row is the last shifted by one end, so a window is set
  // by the crossing's place in the 1100 cycle: 4 of 16 crossings.
  const NeighbourhoodCounts n = crossing_neighbourhoods(named("twill_2_2"));
  EXPECT_EQ(n.crossings(), 16);
  EXPECT_EQ(n.plus1, 4);
  for (int c : n.square) EXPECT_EQ(c, 4);
}

TEST(CrossingNeighbourhoods, SatinHoldsFiveOrbits) {
  // satin 5 (step 2): shifting by (2 ends, 1 pick) maps it onto itself, so
  // its 25 crossings fall in 5 orbits; the 5 x 5 window tells them apart,
  // the plus stencil can only merge some.
  const NeighbourhoodCounts n = crossing_neighbourhoods(named("satin_5"));
  EXPECT_EQ(n.crossings(), 25);
  EXPECT_EQ(n.square[1], 5);
  EXPECT_EQ(n.square[2], 5);
  EXPECT_LE(n.plus1, 5);
  EXPECT_GE(n.plus1, 2);
}

TEST(CrossingNeighbourhoods, ColoursDoNotCount) {
  ClothSpec s = named("plain");
  const Imath::V3f red(0.8f, 0.1f, 0.1f), white(0.9f, 0.9f, 0.9f);
  s.warp.colors = {red, red, red, white, white, white, white, white, white, white, white, white};
  const NeighbourhoodCounts n = crossing_neighbourhoods(s);
  EXPECT_EQ(n.ends, 2);  // the colour-free repeat
  EXPECT_EQ(n.plus1, 2);
}

TEST(CrossingNeighbourhoods, ASpacingSequenceTellsThreadsApart) {
  // Plain weave, every fourth end closer: the repeat is 4 ends, and the
  // close end and its two neighbours now differ from the rest.
  ClothSpec s = named("plain");
  s.warp.spacings_mm = {0.5f, 0.5f, 0.25f, 0.5f};
  const NeighbourhoodCounts n = crossing_neighbourhoods(s);
  EXPECT_EQ(n.ends, 4);
  EXPECT_EQ(n.picks, 2);
  // ends 1, 2, 3 each see the 0.25 end at a different place in the
  // stencil, end 0 does not: 4 kinds of end x 2 lifts each.
  EXPECT_EQ(n.plus1, 8);
}

// Phase bins (material --phase-bins): a class is the plus-1 class and the
// bin of the ply phase of the yarn on top at the crossing, that phase
// computed here from PlyTwist directly, on a 12 x 12 draft of seeded random
// lifts (its smallest repeat is itself: 24 yarns of their own phase).
TEST(CrossingClasses, PhaseBinsSplitEachClassByTheTopYarnsPlyPhase) {
  ClothSpec spec;
  uint64_t state = 12345;
  spec.draft.assign(12, std::vector<int>(12));
  for (auto& row : spec.draft)
    for (int& up : row) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      up = int((state >> 33) & 1u);
    }
  const ClothSpec free = colour_free(spec);
  const int bins = 4;
  const CrossingClasses plain = crossing_classes(free);
  const CrossingClasses binned = crossing_classes(free, CrossingStencil::Plus1, bins);
  ASSERT_EQ(binned.ends, 12);
  ASSERT_EQ(binned.picks, 12);

  const WeaveDraft draft = draft_of(free);
  const ThreadLayout ends = thread_layout(free, draft, true), picks = thread_layout(free, draft, false);
  const PlyTwist ply(free, weave_repeat_mm(free));
  const float two_pi = 2.0f * std::numbers::pi_v<float>, bin = two_pi / float(bins);
  auto wrapped = [&](int e, int p) {
    const float phase = draft.warp_up(p, e) ? ply.phase(true, e, picks.centre_mm(p))
                                            : ply.phase(false, p, ends.centre_mm(e));
    return phase - two_pi * std::floor(phase / two_pi);
  };
  auto bin_of = [&](int e, int p) { return std::min(int(wrapped(e, p) / bin), bins - 1); };
  auto off_centre = [&](int e, int p) {
    return std::abs(wrapped(e, p) - (float(bin_of(e, p)) + 0.5f) * bin);
  };
  // The product of the two partitions: same binned class exactly when the
  // same plain class and the same bin.
  for (int i = 0; i < 144; ++i)
    for (int j = 0; j < 144; ++j) {
      const int ei = i % 12, pi = i / 12, ej = j % 12, pj = j / 12;
      const bool same = binned.at(ei, pi) == binned.at(ej, pj);
      const bool expect = plain.at(ei, pi) == plain.at(ej, pj) && bin_of(ei, pi) == bin_of(ej, pj);
      ASSERT_EQ(same, expect) << "crossings (" << ei << ", " << pi << ") and (" << ej << ", " << pj << ")";
    }
  EXPECT_GT(binned.count(), plain.count());
  EXPECT_LE(binned.count(), bins * plain.count());
  // Each class's representative is its member nearest the bin's centre,
  // and members() gives it first.
  for (int b = 0; b < binned.count(); ++b) {
    const CrossingClasses::Crossing r = binned.representative[size_t(b)];
    EXPECT_EQ(binned.at(r.end, r.pick), b);
    for (int i = 0; i < 144; ++i)
      if (binned.at(i % 12, i / 12) == b) EXPECT_LE(off_centre(r.end, r.pick), off_centre(i % 12, i / 12));
    const std::vector<CrossingClasses::Crossing> m = binned.members(b, 3);
    ASSERT_FALSE(m.empty());
    EXPECT_EQ(m[0].end, r.end);
    EXPECT_EQ(m[0].pick, r.pick);
  }
}

}  // namespace
}  // namespace clothbake
