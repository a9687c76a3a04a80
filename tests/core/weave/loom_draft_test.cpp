// The loom's drawdown rules (core/weave/loom_draft.h, docs/formats/wif.md).

#include "core/weave/loom_draft.h"

#include <cmath>

#include <gtest/gtest.h>

namespace clothbake {
namespace {

// A straight-threaded 4-shaft 2/2 twill: end e on shaft e+1, treadle t ties
// shafts t and t+1, treadled 1, 2, 3, 4.
LoomDraft twill() {
  LoomDraft d;
  d.ends = d.picks = d.shafts = d.treadles = 4;
  d.threading = {{1}, {2}, {3}, {4}};
  d.tieup = {{1, 2}, {2, 3}, {3, 4}, {4, 1}};
  d.treadling = {{1}, {2}, {3}, {4}};
  return d;
}

using Rows = std::vector<std::vector<int>>;

TEST(LoomDraft, RisingShedLiftsTheTiedShafts) {
  EXPECT_EQ(drawdown(twill()), (Rows{{1, 1, 0, 0}, {0, 1, 1, 0}, {0, 0, 1, 1}, {1, 0, 0, 1}}));
}

TEST(LoomDraft, SinkingShedIsTheComplementForSingleShaftEnds) {
  LoomDraft d = twill();
  d.rising_shed = false;
  EXPECT_EQ(drawdown(d), (Rows{{0, 0, 1, 1}, {1, 0, 0, 1}, {1, 1, 0, 0}, {0, 1, 1, 0}}));
}

TEST(LoomDraft, LiftplanTwinGivesTheSameDrawdown) {
  LoomDraft d = twill();
  LoomDraft l = twill();
  l.has_liftplan = true;
  l.liftplan = {{1, 2}, {2, 3}, {3, 4}, {4, 1}};
  l.treadling = {{2}, {2}, {2}, {2}};  // ignored when a liftplan is there
  EXPECT_EQ(drawdown(d), drawdown(l));
}

TEST(LoomDraft, SeveralShaftsPerEndAndSeveralTreadlesPerPick) {
  LoomDraft d = twill();
  d.threading = {{1, 3}, {2}, {}, {4}};   // end 1 on two shafts, end 3 on none
  d.treadling = {{1, 3}, {}, {3}, {0}};  // two treadles; none; one; a 0 entry
  // pick 1 lifts 1,2,3,4: every threaded end up, the unthreaded end 3 stays down.
  // pick 2 lifts nothing; pick 3 lifts 3,4: end 1 (on 3) and end 4.
  EXPECT_EQ(drawdown(d), (Rows{{1, 1, 0, 1}, {0, 0, 0, 0}, {1, 0, 0, 1}, {0, 0, 0, 0}}));
  d.rising_shed = false;  // sinking: up = threaded and none of its shafts listed
  EXPECT_EQ(drawdown(d), (Rows{{0, 0, 0, 0}, {1, 1, 0, 1}, {0, 1, 0, 0}, {1, 1, 0, 1}}));
}

TEST(LoomDraft, ATreadleWithoutATieUpRowLiftsNothing) {
  LoomDraft d = twill();
  d.treadles = 6;
  d.treadling = {{5}, {6}, {1, 6}, {4}};
  EXPECT_EQ(drawdown(d)[0], (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(drawdown(d)[1], (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(drawdown(d)[2], (std::vector<int>{1, 1, 0, 0}));
}

TEST(LoomDraft, DisplayColoursBecomeLinear) {
  const Imath::V3f a = display_to_linear({0.0f, 255.0f, 127.5f}, 0.0f, 255.0f);
  EXPECT_FLOAT_EQ(a.x, 0.0f);
  EXPECT_FLOAT_EQ(a.y, 1.0f);
  EXPECT_NEAR(a.z, std::pow((0.5 + 0.055) / 1.055, 2.4), 1e-6);  // 0.21404
  const Imath::V3f b = display_to_linear({999.0f, 0.0f, 10.0f}, 0.0f, 999.0f);
  EXPECT_FLOAT_EQ(b.x, 1.0f);
  EXPECT_NEAR(b.z, 10.0 / 999.0 / 12.92, 1e-7);  // the linear toe of the curve
}

}  // namespace
}  // namespace clothbake
