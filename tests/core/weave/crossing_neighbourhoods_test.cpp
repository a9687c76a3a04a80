// The distinct neighbourhoods of a weave's crossings (core/weave/
// crossing_neighbourhoods.h): the counts of named weaves, known by hand, and
// what changes them (spacings) and what does not (colours).

#include "core/weave/crossing_neighbourhoods.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace clothbake
