#include "core/material_bake/bake_rules.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace clothbake {
namespace {

// The advice clothbake material prints for wi_32twill (62 x 62 threads) at
// 8 texels: 0.13 texels per thread, and 256 the smallest power of 2 giving 4.
TEST(TexelAdvice, FewTexelsPerThreadAdviseThePowerOfTwoThatGivesFour) {
  MaterialSettings s;
  s.texels = 8;
  const TexelAdvice a = texel_advice(s, 62, 62);
  EXPECT_EQ(a.threads_across, 62);
  EXPECT_DOUBLE_EQ(a.texels_per_thread, 8.0 / 62.0);
  EXPECT_TRUE(a.too_few());
  EXPECT_EQ(a.advised_texels, 256);
}

TEST(TexelAdvice, UnknownThreadsAndCrossingsGiveNoWarning) {
  MaterialSettings s;
  s.texels = 8;
  EXPECT_FALSE(texel_advice(s, 0, 0).known());
  EXPECT_FALSE(texel_advice(s, 0, 0).too_few());
  // Addressed per crossing, R texels span one thread whatever the repeat.
  s.address = MaterialAddress::Crossings;
  const TexelAdvice a = texel_advice(s, 480, 91);
  EXPECT_EQ(a.threads_across, 1);
  EXPECT_FALSE(a.too_few());
}

std::string refused_field(const MaterialSource& src, const MaterialSettings& s,
                          const MaterialShard& shard = {}) {
  try {
    check_material_bake(src, s, shard);
  } catch (const InputError& e) {
    return e.field();
  }
  return "";
}

// The rules name the setting, never a flag: the CLI maps names to flags.
TEST(CheckMaterialBake, NamesTheSettingThatCannotBeBaked) {
  MaterialSource rgb;
  rgb.rgb_reason = "RGB was asked (parts)";
  MaterialSource free;
  free.parts = MaterialParts::SpecularWarpWeft;
  MaterialSettings s;
  EXPECT_EQ(refused_field(rgb, s), "");
  s.address = MaterialAddress::Crossings;
  EXPECT_EQ(refused_field(rgb, s), "address");
  s.parts = MaterialParts::SpecularWarpWeft;
  EXPECT_EQ(refused_field(rgb, s), "parts");
  EXPECT_EQ(refused_field(free, s), "");
  EXPECT_EQ(refused_field(free, s, MaterialShard{0, 2}), "shard");
  s.address = MaterialAddress::Repeat;
  EXPECT_EQ(refused_field(free, s, MaterialShard{0, 4096}), "shard");
  s.texels = 48;
  EXPECT_EQ(refused_field(free, s), "texels");
  s.texels = 32;
  free.optics.depth_scale = 0.0f;
  EXPECT_EQ(refused_field(free, s), "depth_scale");
}

}  // namespace
}  // namespace clothbake
