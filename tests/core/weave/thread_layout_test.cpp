// Per-thread colours and sizes, the repeat as a least common multiple, and
// the automatic resolution (core/weave/thread_layout.h, cloth_spec.h).

#include "core/weave/thread_layout.h"

#include <gtest/gtest.h>

#include "core/texture/crossings.h"
#include "core/texture/volume_generator.h"
#include "core/util/error.h"
#include "core/weave/drawdown_image.h"
#include "core/weave/weave.h"

namespace clothbake {
namespace {

const Imath::V3f k_red(0.8f, 0.05f, 0.05f), k_white(0.9f, 0.9f, 0.9f), k_blue(0.05f, 0.1f, 0.7f);

TEST(ThreadLayout, RepeatIsTheLeastCommonMultiple) {
  YarnSpec y;
  y.colors = {k_red, k_red, k_red, k_white, k_white, k_white,
              k_white, k_white, k_white, k_white, k_white, k_white};  // a 12-end stripe
  EXPECT_EQ(ThreadLayout(y, 2, "warp").count(), 12);  // plain: 2 | 12
  EXPECT_EQ(ThreadLayout(y, 3, "warp").count(), 12);  // twill 2/1
  EXPECT_EQ(ThreadLayout(y, 5, "warp").count(), 60);  // satin 5
  y.colors.resize(7, k_blue);
  EXPECT_EQ(ThreadLayout(y, 4, "warp").count(), 28);
  y.spacings_mm = {0.5f, 0.25f, 0.25f};
  EXPECT_EQ(ThreadLayout(y, 4, "warp").count(), 84);
}

TEST(ThreadLayout, ColoursRepeatAlongTheThreads) {
  YarnSpec y;
  y.colors = {k_red, k_white, k_blue};
  const ThreadLayout l(y, 2, "warp");
  ASSERT_EQ(l.count(), 6);
  for (int i = -6; i < 12; ++i) EXPECT_EQ(l.color(i), y.colors[((i % 3) + 3) % 3]) << i;
}

TEST(ThreadLayout, UnevenSpacingPlacesCentresAndTiles) {
  YarnSpec y;
  y.spacings_mm = {1.0f, 0.5f, 0.5f};
  y.widths_mm = {0.8f, 0.4f, 0.4f};
  const ThreadLayout l(y, 3, "warp");
  EXPECT_FLOAT_EQ(l.repeat_mm(), 2.0f);
  // The first centre sits half the last gap in, so the repeat tiles.
  EXPECT_FLOAT_EQ(l.centre_mm(0), 0.25f);
  EXPECT_FLOAT_EQ(l.centre_mm(1), 1.25f);
  EXPECT_FLOAT_EQ(l.centre_mm(2), 1.75f);
  EXPECT_FLOAT_EQ(l.centre_mm(3), 2.25f);
  EXPECT_FLOAT_EQ(l.centre_mm(-1), -0.25f);
  float t, gap;
  EXPECT_EQ(l.locate(0.75f, t, gap), 0);
  EXPECT_FLOAT_EQ(t, 0.5f);
  EXPECT_FLOAT_EQ(gap, 1.0f);
  EXPECT_EQ(l.locate(0.0f, t, gap), -1);  // before the first centre: the previous repeat's last
  EXPECT_FLOAT_EQ(gap, 0.5f);
  EXPECT_FLOAT_EQ(t, 0.5f);
  EXPECT_EQ(l.locate(3.5f, t, gap), 4);  // one repeat on, thread 1
  EXPECT_FLOAT_EQ(l.width_mm(4), 0.4f);
}

TEST(ThreadLayout, TooLongARepeatIsRefused) {
  YarnSpec y;
  y.colors.assign(4093, k_red);  // prime against 2: lcm 8186
  try {
    (void)ThreadLayout(y, 2, "warp");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "warp.colors");
  }
}

TEST(Resolution, AutomaticPerRepeatForPatternsAndPerThreadForDrafts) {
  ClothSpec s;
  EXPECT_EQ(resolved_resolution(s).cells_x, 64);  // named: as it always was
  s.warp.colors = {k_red, k_red, k_red, k_white, k_white, k_white};
  EXPECT_EQ(resolved_resolution(s).cells_x, 64 * 3);  // 3 plain repeats, same cells each
  EXPECT_EQ(resolved_resolution(s).cells_y, 64);
  ClothSpec d;
  d.draft.assign(480, std::vector<int>(91, 0));
  d.draft[0][0] = 1;
  const ResolutionSpec r = resolved_resolution(d);
  EXPECT_EQ(r.cells_x, 8 * 91);
  EXPECT_EQ(r.cells_y, 8 * 480);
  d.draft = {{1, 0}, {0, 1}};
  EXPECT_EQ(resolved_resolution(d).cells_x, 64);  // at least 64: a small draft as before
  d.resolution.cells_x = 10;
  EXPECT_EQ(resolved_resolution(d).cells_x, 10);  // explicit wins
}

// The must-show stripe spec: a plain weave with a 12-end colour stripe has a
// 12-end repeat, and at every crossing the top yarn's colour is its thread's.
TEST(Stripe, RepeatAndColoursAtTheRightEnds) {
  ClothSpec s;
  s.pattern = "plain";
  s.warp.colors = {k_red, k_red, k_red, k_red, k_white, k_white,
                   k_white, k_white, k_blue, k_blue, k_white, k_white};
  s.weft.color = k_white;
  s.shading.variation = 0.0f;
  s.shading.diffuse_top = s.shading.diffuse_bottom = 1.0f;
  s.density.noise_amplitude = 0.0f;
  s.resolution.layers = 8;
  s.resolution.supersample = 1;
  int ends = 0, picks = 0;
  repeat_threads(s, ends, picks);
  EXPECT_EQ(ends, 12);
  EXPECT_EQ(picks, 2);
  const VolumeTexture v = generate_volume(s, uint64_t(1) << 32);
  EXPECT_EQ(v.nx(), 64 * 6);
  EXPECT_FLOAT_EQ(v.size_mm().x, 12 * s.warp.spacing_mm);
  const Image tops = crossing_tops(v, s);
  ASSERT_EQ(tops.width, 12);
  ASSERT_EQ(tops.height, 2);
  const WeaveDraft plain = WeaveDraft::named("plain");
  for (int p = 0; p < 2; ++p)
    for (int e = 0; e < 12; ++e) {
      const float* px = tops.at(e, p);
      const bool up = plain.warp_up(p, e);
      EXPECT_EQ(px[3], up ? 1.0f : 2.0f) << e << "," << p;
      const Imath::V3f want = up ? s.warp.colors[e] : s.weft.color;
      for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(px[c], want[c]) << e << "," << p;
    }
  // The drawdown shows the same: end 9 (blue) up at pick 2 (row 0 is the top, the last pick).
  const Image dd = drawdown_image(s, 1);
  ASSERT_EQ(dd.width, 12);
  const bool up_8_1 = plain.warp_up(1, 8);
  const Imath::V3f want = up_8_1 ? k_blue : k_white;
  EXPECT_FLOAT_EQ(dd.at(8, 0)[2], want[2]);
}

// Spacing per thread moves the yarns: a thread twice as far from its
// neighbours leaves a gap the crossing image sees as the weft below.
TEST(Stripe, PerThreadSpacingAndWidthMoveTheYarns) {
  ClothSpec s;
  s.draft = {{1, 0, 1, 0}, {0, 1, 0, 1}};
  s.warp.spacings_mm = {0.5f, 0.5f, 1.0f, 0.5f};
  s.warp.widths_mm = {0.44f, 0.44f, 0.9f, 0.44f};
  s.resolution.cells_per_thread = 16;
  s.resolution.supersample = 1;
  const VolumeTexture v = generate_volume(s, uint64_t(1) << 32);
  EXPECT_FLOAT_EQ(v.size_mm().x, 2.5f);
  const Image tops = crossing_tops(v, s);
  for (int p = 0; p < 2; ++p)
    for (int e = 0; e < 4; ++e)
      EXPECT_EQ(tops.at(e, p)[3], s.draft[p][e] ? 1.0f : 2.0f) << e << "," << p;
}

}  // namespace
}  // namespace clothbake
