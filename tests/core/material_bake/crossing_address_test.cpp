// A material addressed per crossing (settings.address = Crossings,
// docs/formats/material.md "Addressed per crossing"): one block of texels per
// plus-1 class of crossings, read through the per-crossing index.
//  - the classes of named weaves, counted by hand, agree with the counts
//    `clothbake draft` reports;
//  - where the light fields' window covers the repeat, each block is exactly
//    the whole-repeat bake's texels at its representative crossing (same
//    samples, same fields);
//  - a crossing read through another crossing's block (same class) differs
//    from the whole-repeat bake only by the bake's noise when the cloth has
//    no per-crossing randomness;
//  - every level is the exact box average of the one below inside each block.

#include <cmath>

#include <gtest/gtest.h>

#include "core/material_bake/light_fields.h"
#include "core/material_bake/material_bake.h"
#include "core/texture/volume_generator.h"
#include "core/util/error.h"
#include "core/util/random.h"
#include "core/weave/cloth_colours.h"
#include "core/weave/crossing_neighbourhoods.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr uint64_t k_budget = uint64_t(1) << 32;

/// A named weave made colour-free (what a material is baked from), `cells`
/// cells across its repeat.
ClothSpec spec_of(const char* pattern, int cells) {
  ClothSpec s;
  s.pattern = pattern;
  s.resolution.cells_x = s.resolution.cells_y = cells;
  s.resolution.layers = 8;
  s.resolution.supersample = 1;
  return colour_free(s);
}

/// Per-crossing randomness out: what is left between two crossings of one
/// class is the bake's noise.
ClothSpec without_randomness(ClothSpec s) {
  s.density.noise_amplitude = 0.0f;
  s.shading.variation = 0.0f;
  s.warp.twist_deg = s.weft.twist_deg = 0.0f;
  return s;
}

MaterialSettings settings(MaterialAddress address, int texels, int spp = 2) {
  MaterialSettings s;
  s.address = address;
  s.texels = texels;
  s.directions = 3;
  s.light_directions = 3;
  s.spp = spp;
  s.max_error = 0.0f;  // full rank: the table is the marches
  s.field_supersample = 1;
  s.view_parallax = false;
  s.context = 1;
  s.parts = MaterialParts::SpecularWarpWeft;
  return s;
}

struct Baked {
  ClothSpec spec;
  VolumeTexture volume;
  ClothMaterial material;
};

Baked bake(const ClothSpec& spec, const MaterialSettings& s) {
  Baked b{spec, generate_volume(spec, k_budget), {}};
  const FiberShader shader(FiberModelKind::Table, 8.0f, 24.0f, 32, 1);
  b.material = bake_material(material_source(b.volume, shader, MaterialOptics{}, b.spec), s,
                             k_budget, {}, nullptr);
  return b;
}

TEST(CrossingClasses, NamedWeavesHoldTheirPlus1Counts) {
  for (const auto& [pattern, ends, classes] :
       {std::tuple{"plain", 2, 2}, std::tuple{"twill_2_2", 4, 4}, std::tuple{"satin_5", 5, 5}}) {
    const ClothSpec spec = spec_of(pattern, 20);
    const CrossingClasses c = crossing_classes(spec);
    EXPECT_EQ(c.ends, ends) << pattern;
    EXPECT_EQ(c.count(), classes) << pattern;
    EXPECT_EQ(c.count(), crossing_neighbourhoods(spec).plus1) << pattern;
    EXPECT_EQ(crossing_classes(spec, CrossingStencil::Square1).count(),
              crossing_neighbourhoods(spec).square[0])
        << pattern;
    // Each class's representative is its first crossing, pick-major.
    for (int b = 0; b < c.count(); ++b) {
      const CrossingClasses::Crossing r = c.representative[size_t(b)];
      EXPECT_EQ(c.at(r.end, r.pick), b);
      for (int i = 0; i < r.pick * c.ends + r.end; ++i) EXPECT_NE(c.class_of[size_t(i)], b);
    }
  }
}

// Plain weave: crossings (0, 0) and (1, 1) are one class, (1, 0) and (0, 1)
// the other; the window of one crossing either side spans the 2-thread
// repeat, so the fields are the whole repeat's.
TEST(AddressedMaterial, BlocksAreTheWholeBakeAtTheirRepresentatives) {
  const ClothSpec spec = spec_of("plain", 16);
  const int T = 4;
  const Baked whole = bake(spec, settings(MaterialAddress::Repeat, 2 * T));
  const Baked addressed = bake(spec, settings(MaterialAddress::Crossings, T));
  const ClothMaterial& a = addressed.material;
  const ClothMaterial& w = whole.material;
  ASSERT_EQ(a.crossings.count(), 2);
  ASSERT_EQ(a.layout().level_rows(0), 2 * T);
  double worst = 0.0, mean = 0.0;
  int n = 0;
  for (int b = 0; b < a.crossings.count(); ++b) {
    const CrossingClasses::Crossing c = a.crossings.representative[size_t(b)];
    for (int v = 0; v < a.view_count(); ++v)
      for (int y = 0; y < T; ++y)
        for (int x = 0; x < T; ++x) {
          EXPECT_NEAR(a.texel_alpha(0, v, x, b * T + y),
                      w.texel_alpha(0, v, c.end * T + x, c.pick * T + y), 1e-5f);
          for (int l = 0; l < a.light_count(); ++l) {
            const V3f got = a.texel_radiance(0, v, l, x, b * T + y);
            const V3f want = w.texel_radiance(0, v, l, c.end * T + x, c.pick * T + y);
            worst = std::max(worst, double((got - want).length()));
            mean += want.length();
            ++n;
          }
        }
  }
  mean /= n;
  ASSERT_GT(mean, 1e-3);
  // Float rounding of the sample positions only (the same seeds and fields).
  EXPECT_LT(worst, 1e-3 * (1.0 + mean)) << "mean " << mean;
}

// --members: a block is the mean of its members' marches. On the 2/2 twill
// (4 ends) a window of 2 crossings either side spans the repeat, so each
// member's fields are the whole repeat's and its samples the whole bake's:
// with every member (4 a class) the block is the mean of the whole bake's
// texels at the class's crossings, to float rounding.
TEST(AddressedMaterial, MembersAverageTheirCrossings) {
  const ClothSpec spec = spec_of("twill_2_2", 32);
  const int T = 2;
  const Baked whole = bake(spec, settings(MaterialAddress::Repeat, 4 * T));
  MaterialSettings s = settings(MaterialAddress::Crossings, T);
  s.context = 2;
  s.members = 16;
  const Baked addressed = bake(spec, s);
  const ClothMaterial& a = addressed.material;
  const ClothMaterial& w = whole.material;
  ASSERT_EQ(a.crossings.count(), 4);
  double worst = 0.0, mean = 0.0, spread = 0.0;
  int n = 0;
  for (int b = 0; b < a.crossings.count(); ++b) {
    const std::vector<CrossingClasses::Crossing> members = a.crossings.members(b, 16);
    ASSERT_EQ(members.size(), 4u);
    for (int v = 0; v < a.view_count(); ++v)
      for (int y = 0; y < T; ++y)
        for (int x = 0; x < T; ++x)
          for (int l = 0; l < a.light_count(); l += 2) {
            V3f want(0.0f);
            for (const CrossingClasses::Crossing& c : members)
              want += w.texel_radiance(0, v, l, c.end * T + x, c.pick * T + y) / 4.0f;
            const CrossingClasses::Crossing r = members.front();
            spread +=
                double((w.texel_radiance(0, v, l, r.end * T + x, r.pick * T + y) - want).length());
            worst =
                std::max(worst, double((a.texel_radiance(0, v, l, x, b * T + y) - want).length()));
            mean += want.length();
            ++n;
          }
  }
  mean /= n;
  spread /= n;
  ASSERT_GT(mean, 1e-3);
  EXPECT_GT(spread, 1e-2 * mean) << "the members differ (randomness, noise): the mean is a test";
  EXPECT_LT(worst, 1e-3 * (1.0 + mean)) << "mean " << mean;
}

// Shown through shade(): at every point of the repeat, views and lights
// tried, the addressed material against the whole-repeat bake differs by no
// more than two whole-repeat bakes of different seeds do (the bake's noise),
// with a quarter margin: crossing (1, 1) reads (0, 0)'s block, and without
// per-crossing randomness the two crossings are the same cloth.
TEST(AddressedMaterial, ShadesAsTheWholeRepeatWithinTheBakesNoise) {
  const ClothSpec spec = without_randomness(spec_of("twill_2_2", 32));
  const int T = 4;
  MaterialSettings ws = settings(MaterialAddress::Repeat, 4 * T, 4);
  const Baked whole = bake(spec, ws);
  ws.seed = 2;
  const Baked whole2 = bake(spec, ws);
  MaterialSettings as = settings(MaterialAddress::Crossings, T, 4);
  as.seed = 3;
  as.context = 2;
  const Baked addressed = bake(spec, as);
  ASSERT_EQ(addressed.material.crossings.count(), 4);  // 4 of 16 crossings
  const ClothMaterial::Light light{V3f(0.3f, -0.4f, 0.866f).normalized(), V3f(1.0f, 0.9f, 0.8f)};
  double noise = 0.0, diff = 0.0, norm = 0.0;
  const V3f size = whole.material.repeat_mm;
  for (int i = 0; i < 400; ++i) {
    const float x = (float(i % 20) + 0.37f) / 20.0f * size.x;
    const float y = (float(i / 20) + 0.61f) / 20.0f * size.y;
    const float theta = 0.15f + 1.0f * float(i % 7) / 7.0f, phi = 0.9f * float(i);
    const V3f to_eye(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                     std::cos(theta));
    const V3f w = whole.material.shade(x, y, 1.0f, to_eye, std::span(&light, 1)).radiance;
    const V3f w2 = whole2.material.shade(x, y, 1.0f, to_eye, std::span(&light, 1)).radiance;
    const V3f a = addressed.material.shade(x, y, 1.0f, to_eye, std::span(&light, 1)).radiance;
    noise += double((w2 - w).length2());
    diff += double((a - w).length2());
    norm += double(w.length2());
  }
  ASSERT_GT(norm, 0.0);
  const double noise_rel = std::sqrt(noise / norm), diff_rel = std::sqrt(diff / norm);
  EXPECT_GT(noise_rel, 0.0);
  EXPECT_LT(diff_rel, 1.25 * noise_rel) << "addressed " << diff_rel << ", noise " << noise_rel;
}

TEST(AddressedMaterial, LevelsAreBoxAveragesInsideEachBlock) {
  const ClothSpec spec = spec_of("twill_2_2", 32);
  MaterialSettings s = settings(MaterialAddress::Crossings, 4);
  s.max_error = 0.05f;
  const ClothMaterial m = bake(spec, s).material;
  ASSERT_EQ(m.levels(), 3);  // 4, 2, 1 texels a crossing
  for (int level = 1; level < m.levels(); ++level) {
    const int side = m.level_side(level);
    ASSERT_EQ(m.layout().level_rows(level), side * m.crossings.count());
    for (int v = 0; v < m.view_count(); ++v)
      for (int y = 0; y < m.layout().level_rows(level); ++y)
        for (int x = 0; x < side; ++x) {
          const float a = 0.25f * ((m.texel_alpha(level - 1, v, 2 * x, 2 * y) +
                                    m.texel_alpha(level - 1, v, 2 * x + 1, 2 * y)) +
                                   (m.texel_alpha(level - 1, v, 2 * x, 2 * y + 1) +
                                    m.texel_alpha(level - 1, v, 2 * x + 1, 2 * y + 1)));
          EXPECT_EQ(m.texel_alpha(level, v, x, y), a);
        }
  }
  // The top level: one texel a crossing, its block's mean, never a neighbour's.
  const int top = m.levels() - 1;
  for (int v = 0; v < m.view_count(); v += 3)
    for (int b = 0; b < m.crossings.count(); ++b)
      for (int l = 0; l < m.light_count(); l += 4) {
        V3f mean(0.0f);
        for (int y = 0; y < 4; ++y)
          for (int x = 0; x < 4; ++x) mean += m.texel_radiance(0, v, l, x, b * 4 + y) / 16.0f;
        EXPECT_NEAR((m.texel_radiance(top, v, l, 0, b) - mean).length(), 0.0f,
                    1e-6f * (1.0f + mean.length()));
      }
}

TEST(AddressedMaterial, NeedsColourFreePartsAndAWholeBake) {
  const ClothSpec spec = spec_of("plain", 8);
  const VolumeTexture volume = generate_volume(spec, k_budget);
  const FiberShader shader(FiberModelKind::Table, 8.0f, 24.0f, 32, 1);
  MaterialSettings s = settings(MaterialAddress::Crossings, 2);
  s.parts = MaterialParts::Rgb;
  try {
    bake_material(material_source(volume, shader, MaterialOptics{}), s, k_budget);
    FAIL() << "an RGB material addressed per crossing was baked";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "address");
  }
  s.parts = MaterialParts::SpecularWarpWeft;
  try {
    bake_material(material_source(volume, shader, MaterialOptics{}, spec), s, k_budget, {}, nullptr,
                  MaterialShard{0, 2});
    FAIL() << "a part of an addressed bake was baked";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "shard");
  }
}

}  // namespace
}  // namespace clothbake

namespace clothbake {
namespace {
// A window's light fields against the whole repeat's, at points over the
// window's centre crossing, lights from 80 degrees to 20 above and from
// below: the mean absolute transmittance difference measured at most 2.2e-7
// (a path toward the light leaves the centre crossing's neighbours only
// once the cloth has stopped it); bound 1e-3.
TEST(LightFields, AWindowMatchesTheWholeRepeatAtItsCentre) {
  ClothSpec spec;
  spec.pattern = "twill_2_2";
  spec.resolution.cells_x = spec.resolution.cells_y = 64;  // 16 cells a thread
  spec.resolution.layers = 16;
  spec.resolution.supersample = 1;
  const VolumeTexture volume = generate_volume(spec, k_budget);
  std::vector<V3f> dirs;
  for (float elev_deg : {80.0f, 45.0f, 20.0f, -45.0f}) {
    const float e = elev_deg * 3.14159265f / 180.0f;
    dirs.push_back(V3f(0.8f * std::cos(e), 0.6f * std::cos(e), std::sin(e)).normalized());
  }
  const LightFieldSet whole = LightFieldSet::build(volume, dirs, 40.0f, 1);
  // Crossing (end 1, pick 2) and one crossing either side: cells 0 .. 47 in
  // x, 16 .. 63 in y, of the 64 x 64 repeat (16 cells a thread).
  const LightFieldSet window = LightFieldSet::build_window(volume, 0, 16, 48, 48, dirs, 40.0f, 1);
  const V3f size = volume.size_mm();
  std::vector<double> diff(dirs.size(), 0.0);
  std::vector<float> a(dirs.size()), b(dirs.size());
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const V3f p((1.0f + unit_float(hash_key(3, i, 0))) / 4.0f * size.x,
                (2.0f + unit_float(hash_key(3, i, 1))) / 4.0f * size.y,
                unit_float(hash_key(3, i, 2)) * size.z);
    whole.transmittances(p, a.data());
    window.transmittances(p, b.data());
    for (size_t d = 0; d < dirs.size(); ++d) diff[d] += std::fabs(double(a[d] - b[d])) / n;
  }
  for (size_t d = 0; d < dirs.size(); ++d) EXPECT_LT(diff[d], 1e-3) << "direction " << d;
}
}  // namespace
}  // namespace clothbake
