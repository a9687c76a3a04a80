#include "core/weave/weave.h"

#include <functional>
#include <tuple>

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace clothbake {
namespace {

int ups_in_column(const WeaveDraft& d, int end) {
  int n = 0;
  for (int p = 0; p < d.picks(); ++p) n += d.warp_up(p, end);
  return n;
}
int ups_in_row(const WeaveDraft& d, int pick) {
  int n = 0;
  for (int e = 0; e < d.ends(); ++e) n += d.warp_up(pick, e);
  return n;
}

TEST(WeaveDraft, PlainIsACheckerboard) {
  const WeaveDraft d = WeaveDraft::named("plain");
  ASSERT_EQ(d.picks(), 2);
  ASSERT_EQ(d.ends(), 2);
  for (int p = 0; p < 2; ++p)
    for (int e = 0; e < 2; ++e) EXPECT_EQ(d.warp_up(p, e), (p + e) % 2 == 0);
}

TEST(WeaveDraft, TwillsFloatAndStepOneEndPerPick) {
  for (auto [name, up, n] : {std::tuple{"twill_2_1", 2, 3}, std::tuple{"twill_2_2", 2, 4}}) {
    const WeaveDraft d = WeaveDraft::named(name);
    ASSERT_EQ(d.picks(), n) << name;
    for (int e = 0; e < n; ++e) EXPECT_EQ(ups_in_column(d, e), up) << name;
    // The diagonal: pick p+1 is pick p shifted by one end.
    for (int p = 0; p < n; ++p)
      for (int e = 0; e < n; ++e) EXPECT_EQ(d.warp_up(p + 1, e + 1), d.warp_up(p, e)) << name;
  }
}

TEST(WeaveDraft, SatinsHaveOneIsolatedFloatPerPickAndEnd) {
  for (auto [name, n] : {std::pair{"satin_5", 5}, std::pair{"satin_8", 8}}) {
    const WeaveDraft d = WeaveDraft::named(name);
    ASSERT_EQ(d.picks(), n);
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(ups_in_row(d, i), 1) << name;
      EXPECT_EQ(ups_in_column(d, i), 1) << name;
    }
    // Satin, not twill: interlacings of neighbouring picks never touch.
    for (int p = 0; p < n; ++p)
      for (int e = 0; e < n; ++e)
        if (d.warp_up(p, e)) {
          EXPECT_FALSE(d.warp_up(p + 1, e + 1)) << name;
          EXPECT_FALSE(d.warp_up(p + 1, e - 1)) << name;
        }
  }
}

TEST(WeaveDraft, BasketIsPlainWithPairedYarns) {
  const WeaveDraft d = WeaveDraft::named("basket_2x2");
  const WeaveDraft plain = WeaveDraft::named("plain");
  for (int p = 0; p < 4; ++p)
    for (int e = 0; e < 4; ++e) EXPECT_EQ(d.warp_up(p, e), plain.warp_up(p / 2, e / 2));
}

TEST(WeaveDraft, IndicesWrapPeriodically) {
  const WeaveDraft d = WeaveDraft::named("satin_5");
  for (int p = -7; p < 12; ++p)
    for (int e = -9; e < 13; ++e) EXPECT_EQ(d.warp_up(p, e), d.warp_up(p + 5, e - 10));
}

TEST(WeaveDraft, CustomDraftIsUsedAsGiven) {
  const WeaveDraft d({{1, 1, 0}, {0, 1, 1}, {1, 0, 1}});
  EXPECT_TRUE(d.warp_up(0, 0));
  EXPECT_FALSE(d.warp_up(1, 0));
  EXPECT_TRUE(d.warp_up(2, 2));
}

std::string error_field(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "(no error)";
}

// A pick over (or under) every end is a float, real cloth: kept, not refused.
TEST(WeaveDraft, FloatsAreKept) {
  const WeaveDraft d({{1, 0}, {0, 0}, {1, 1}});
  EXPECT_EQ(d.picks(), 3);
  EXPECT_FALSE(d.warp_up(1, 0));
  EXPECT_FALSE(d.warp_up(1, 1));
  EXPECT_TRUE(d.warp_up(2, 0));
  EXPECT_TRUE(d.warp_up(2, 1));
}

TEST(WeaveDraft, BadDraftsNameTheField) {
  EXPECT_EQ(error_field([] { WeaveDraft(std::vector<std::vector<int>>{}); }), "weave.draft");
  EXPECT_EQ(error_field([] { WeaveDraft({{1, 0}, {0}}); }), "weave.draft[1]");
  EXPECT_EQ(error_field([] { WeaveDraft({{1, 2}, {0, 1}}); }), "weave.draft[0][1]");
  EXPECT_EQ(error_field([] { WeaveDraft(std::vector<std::vector<int>>(1, std::vector<int>(4097, 0))); }),
            "weave.draft");  // over k_max_draft_threads
  EXPECT_EQ(error_field([] { WeaveDraft::named("herringbone"); }), "weave.pattern");
}

TEST(WeaveDraft, SmallestRepeatOfAWholeThreading) {
  // A plain weave written over 6 x 4 threads (as a WIF holds a threading):
  // its repeat is 2 x 2, the same crossing at every index.
  std::vector<std::vector<int>> m(4, std::vector<int>(6));
  for (int p = 0; p < 4; ++p)
    for (int e = 0; e < 6; ++e) m[size_t(p)][size_t(e)] = (p + e) % 2 == 0 ? 1 : 0;
  const WeaveDraft whole(m), small = whole.smallest_repeat();
  EXPECT_EQ(small.picks(), 2);
  EXPECT_EQ(small.ends(), 2);
  for (int p = -5; p < 9; ++p)
    for (int e = -7; e < 13; ++e) EXPECT_EQ(small.warp_up(p, e), whole.warp_up(p, e)) << p << " " << e;
  // Periods along each axis apart: 2/1 twill written over 6 ends, 3 picks.
  const WeaveDraft twill = WeaveDraft::named("twill_2_1");
  std::vector<std::vector<int>> t(3, std::vector<int>(6));
  for (int p = 0; p < 3; ++p)
    for (int e = 0; e < 6; ++e) t[size_t(p)][size_t(e)] = twill.warp_up(p, e) ? 1 : 0;
  EXPECT_EQ(WeaveDraft(t).smallest_repeat().ends(), 3);
  EXPECT_EQ(WeaveDraft(t).smallest_repeat().picks(), 3);
  // A draft that does not repeat inside itself stays as it is.
  std::vector<std::vector<int>> odd = {{1, 0, 0}, {0, 1, 1}};
  EXPECT_EQ(WeaveDraft(odd).smallest_repeat().ends(), 3);
  EXPECT_EQ(WeaveDraft(odd).smallest_repeat().picks(), 2);
}

}  // namespace
}  // namespace clothbake
