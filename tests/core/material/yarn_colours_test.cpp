// Colour-free materials (docs/formats/material.md, "Colour-free parts"): the
// colour strips' exact values and box averages, the colour-free cloth and the
// field a difference names, and the linearity the whole scheme rests on.
#include "core/material/yarn_colours.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/material/material_shader.h"
#include "core/material_bake/material_bake.h"
#include "core/scene/cloth_scene.h"
#include "core/texture/volume_generator.h"
#include "core/util/error.h"
#include "core/weave/cloth_colours.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr uint64_t k_budget = uint64_t(1) << 32;
const V3f k_red(1, 0, 0), k_green(0, 1, 0), k_blue(0, 0, 1);

void expect_near(const V3f& a, const V3f& b, const char* what, int i) {
  EXPECT_NEAR((a - b).length(), 0.0f, 1e-6f)
      << what << " " << i << ": (" << a.x << ", " << a.y << ", " << a.z << ") against (" << b.x
      << ", " << b.y << ", " << b.z << ")";
}

// Two threads at 0.25 and 0.75 of a 1 mm repeat: thread 0 owns [0, 0.5),
// thread 1 [0.5, 1); 8 texels fall 4 on each; the coarser levels are the
// averages (level 3: the mean of both).
TEST(ColourStrip, EvenThreadsFallOnWholeTexels) {
  const float centres[] = {0.25f, 0.75f};
  const V3f colours[] = {k_red, k_blue};
  const ColourStrip s = colour_strip(centres, 1.0f, colours, 8, 4);
  ASSERT_EQ(s.repeats, 1);
  ASSERT_EQ(s.levels.size(), 4u);
  for (int i = 0; i < 8; ++i) expect_near(s.levels[0][i], i < 4 ? k_red : k_blue, "level 0", i);
  for (int i = 0; i < 4; ++i) expect_near(s.levels[1][i], i < 2 ? k_red : k_blue, "level 1", i);
  expect_near(s.levels[3][0], 0.5f * (k_red + k_blue), "level 3", 0);
}

// Off-centre threads (0.3, 0.8): thread 1 owns [0.55, 1.05), wrapping to
// cover [0, 0.05) of the next repeat; a texel of 0.25 mm straddling a
// boundary takes the colours by length: 0.2 / 0.8.
TEST(ColourStrip, StraddlingTexelsAreLengthWeighted) {
  const float centres[] = {0.3f, 0.8f};
  const V3f colours[] = {k_red, k_blue};
  const ColourStrip s = colour_strip(centres, 1.0f, colours, 4, 3);
  expect_near(s.levels[0][0], 0.2f * k_blue + 0.8f * k_red, "texel", 0);
  expect_near(s.levels[0][1], k_red, "texel", 1);
  expect_near(s.levels[0][2], 0.2f * k_red + 0.8f * k_blue, "texel", 2);
  expect_near(s.levels[0][3], k_blue, "texel", 3);
}

// Three colours on a two-thread repeat: the colours repeat every 3 repeats
// (q = 3), each thread's texels its own colour in turn; every level is the
// exact box average of level 0.
TEST(ColourStrip, ASequenceLongerThanTheRepeatSpansSeveral) {
  const float centres[] = {0.25f, 0.75f};
  const V3f colours[] = {k_red, k_green, k_blue};
  const ColourStrip s = colour_strip(centres, 1.0f, colours, 8, 4);
  ASSERT_EQ(s.repeats, 3);
  ASSERT_EQ(s.levels[0].size(), 24u);
  for (int i = 0; i < 24; ++i) {
    expect_near(s.levels[0][i], colours[(i / 4) % 3], "level 0", i);
    // The neighbours' colours: thread j + 1 and j - 1 (wrapping over the q repeats).
    expect_near(s.plus[0][i], colours[(i / 4 + 1) % 3], "plus", i);
    expect_near(s.minus[0][i], colours[(i / 4 + 2) % 3], "minus", i);
  }
  for (size_t m = 1; m < s.levels.size(); ++m) {
    const size_t n = s.levels[m].size(), span = size_t(1) << m;
    ASSERT_EQ(n, 24u >> m);
    for (size_t i = 0; i < n; ++i) {
      V3f sum(0.0f);
      for (size_t j = 0; j < span; ++j) sum += s.levels[0][i * span + j];
      expect_near(s.levels[m][i], sum / float(span), "box average", int(i));
    }
  }
}

// The colour-free cloth: no colours, the draft's repeat, the coloured cloth's
// cell size; two cloths that differ only in colour agree, any other
// difference is named.
TEST(ColourFree, KeepsTheWeaveAndNamesTheFirstDifference) {
  ClothSpec a;                               // plain, 64 cells per 2-thread repeat
  a.warp.colors = {k_red, k_green, k_blue};  // 6-end repeat
  EXPECT_EQ(resolved_resolution(a).cells_x, 3 * 64);
  const ClothSpec free = colour_free(a);
  EXPECT_TRUE(free.warp.colors.empty());
  EXPECT_EQ(free.warp.color, V3f(k_neutral_albedo));
  EXPECT_EQ(free.draft, (std::vector<std::vector<int>>{{1, 0}, {0, 1}}));
  EXPECT_EQ(free.resolution.cells_x, 64);
  EXPECT_EQ(weave_repeat_mm(a), Imath::V2f(1.0f, 1.0f));
  // Explicit cells count over the weave's repeat too: colours never change them.
  ClothSpec e = a;
  e.resolution.cells_x = 40;
  EXPECT_EQ(resolved_resolution(e).cells_x, 3 * 40);
  EXPECT_EQ(colour_free(e).resolution.cells_x, 40);

  ClothSpec b = a;
  b.weft.color = k_blue;
  b.warp.colors = {k_red, k_red};
  EXPECT_EQ(first_difference(colour_free(a), colour_free(b)).field, "");
  auto field = [&](auto change) {
    ClothSpec c = a;
    change(c);
    return first_difference(colour_free(c), free).field;
  };
  EXPECT_EQ(field([](ClothSpec& c) { c.warp.spacing_mm = 0.6f; }), "warp.spacing_mm");
  EXPECT_EQ(field([](ClothSpec& c) { c.pattern = "twill_2_2"; }), "weave.draft");
  EXPECT_EQ(field([](ClothSpec& c) { c.seed = 2; }), "seed");
  EXPECT_EQ(field([](ClothSpec& c) { c.shading.specular_top = 0.3f; }), "shading.specular_top");
  EXPECT_EQ(field([](ClothSpec& c) { c.resolution.layers = 8; }), "resolution.layers");
  EXPECT_EQ(field([](ClothSpec& c) { c.weft.thickness_mm = 0.2f; }), "weft.thickness_mm");
  // A named pattern and its draft are the same cloth.
  ClothSpec d = a;
  d.draft = {{1, 0}, {0, 1}};
  EXPECT_EQ(first_difference(colour_free(d), free).field, "");
}

// A WIF writes its whole threading: a plain weave written over 6 ends and 4
// picks to carry colour stripes, each end's spacing written out. Without
// its colours it is the 2 x 2 plain weave with the spacings' own period, at
// the cell size the written cloth resolves to; the same cloth written once
// gives the same colour-free spec. A draft that does not repeat stays whole.
TEST(ColourFree, ADraftWrittenOverItsColourRepeatIsCutToItsWeave) {
  ClothSpec written;
  written.draft = {{1, 0, 1, 0, 1, 0}, {0, 1, 0, 1, 0, 1}, {1, 0, 1, 0, 1, 0}, {0, 1, 0, 1, 0, 1}};
  written.warp.spacings_mm = {0.5f, 0.6f, 0.5f, 0.6f, 0.5f, 0.6f};
  written.warp.colors = {k_red, k_red, k_green, k_green, k_blue, k_blue};
  written.weft.colors = {k_blue, k_blue, k_red, k_red};
  written.resolution.cells_x = 66;  // 6 ends over 3.3 mm: 20 cells per mm
  written.resolution.cells_y = 32;
  const ClothSpec free = colour_free(written);
  EXPECT_EQ(free.draft, (std::vector<std::vector<int>>{{1, 0}, {0, 1}}));
  EXPECT_EQ(free.warp.spacings_mm, (std::vector<float>{0.5f, 0.6f}));
  EXPECT_EQ(free.resolution.cells_x, 22);  // 1.1 mm at 20 per mm
  EXPECT_EQ(free.resolution.cells_y, 16);
  ClothSpec once = written;
  once.draft = {{1, 0}, {0, 1}};
  once.warp.spacings_mm = {0.5f, 0.6f};
  once.warp.colors.clear();
  once.weft.colors.clear();
  once.resolution.cells_x = 22;
  once.resolution.cells_y = 16;
  EXPECT_EQ(first_difference(colour_free(once), free).field, "");
  // A scene's repeats_per_uv still counts the draft as written (3.3 x 2 mm):
  // 3 x 2 repeats of the colour-free cloth.
  EXPECT_NEAR(weave_repeat_mm(written).x, 3.3f, 1e-5f);
  EXPECT_NEAR(weave_repeat_mm(written).y, 2.0f, 1e-6f);
  EXPECT_EQ(colour_free_repeats(written), Imath::V2f(3.0f, 2.0f));
  EXPECT_EQ(colour_free_repeats(once), Imath::V2f(1.0f, 1.0f));

  ClothSpec twill;
  twill.draft = {{1, 1, 0, 0}, {0, 1, 1, 0}, {0, 0, 1, 1}, {1, 0, 0, 1}};
  EXPECT_EQ(colour_free(twill).draft, twill.draft);
}

// A colour sequence spanning q weave repeats tiles the colour-free cloth's
// cells q times: density, tangent and specular the same, diffuse the thread's
// colour times the same scale. So a colour-free material is exactly this
// cloth's, recoloured (no other noise or variation).
TEST(ColourFree, AColourSequenceTilesTheColourFreeCells) {
  ClothSpec spec;
  spec.resolution = {16, 16, 4, 1};
  spec.warp.colors = {V3f(0.4f, 0.1f, 0.1f), V3f(0.1f, 0.3f, 0.1f), V3f(0.1f, 0.1f, 0.35f)};
  const VolumeTexture striped = generate_volume(spec, k_budget);
  const VolumeTexture free = generate_volume(colour_free(spec), k_budget);
  ASSERT_EQ(striped.nx(), 3 * free.nx());
  int compared = 0;
  for (int k = 0; k < free.nz(); ++k)
    for (int j = 0; j < free.ny(); ++j)
      for (int i = 0; i < striped.nx(); ++i) {
        const Cell& a = striped.at(i, j, k);
        const Cell& b = free.at(i % free.nx(), j, k);
        ASSERT_EQ(a.density, b.density) << i << "," << j << "," << k;
        ASSERT_EQ(a.family, b.family);
        ASSERT_EQ(a.tangent, b.tangent);
        ASSERT_EQ(a.specular, b.specular);
        if (a.family != YarnFamily::Warp) continue;
        const int end = int((i + 0.5f) * striped.cell_size_mm().x / spec.warp.spacing_mm);
        const V3f colour = spec.warp.colors[size_t(end % 3)];
        EXPECT_NEAR(a.diffuse.x, colour.x * b.diffuse.x / k_neutral_albedo, 1e-6f);
        ++compared;
      }
  EXPECT_GT(compared, 100);
}

MaterialSettings tiny_settings(MaterialParts parts) {
  MaterialSettings s;
  s.texels = 4;
  s.directions = 3;
  s.light_directions = 3;
  s.spp = 2;
  s.max_error = 0.0f;  // full rank: both tables reconstruct the same marches exactly
  s.field_supersample = 1;
  s.parts = parts;
  return s;
}

// Linearity: a colour-free material shown in colours A equals an RGB
// material baked in colours A, at every point, view and light tried. Both
// march the same samples (same seeds, same cells but for the colours) and at
// full rank both tables reconstruct them exactly, so they agree to float
// rounding, not only within the bake's noise. Colours below 1 / 2 (the
// diffuse scale is at most 2 at the defaults): nothing clamps.
TEST(ColourFree, MaterialInColoursAEqualsABakeInColoursA) {
  ClothSpec spec;
  spec.pattern = "twill_2_2";
  spec.resolution = {16, 16, 8, 1};
  spec.warp.color = V3f(0.45f, 0.10f, 0.05f);
  spec.weft.color = V3f(0.05f, 0.30f, 0.40f);
  const FiberShader shader(FiberModelKind::Table, 8.0f, 24.0f, 32, 1);
  const VolumeTexture coloured = generate_volume(spec, k_budget);
  const ClothSpec free_spec = colour_free(spec);
  const VolumeTexture free = generate_volume(free_spec, k_budget);
  const ClothMaterial rgb = bake_material(material_source(coloured, shader, MaterialOptics{}),
                                          tiny_settings(MaterialParts::Rgb), k_budget);
  ClothMaterial parts =
      bake_material(material_source(free, shader, MaterialOptics{}, free_spec),
                    tiny_settings(MaterialParts::SpecularWarpWeft), k_budget, {}, nullptr);
  parts.set_cloth(free_spec, palette_of(spec));
  ASSERT_EQ(parts.repeat_mm, rgb.repeat_mm);
  double worst = 0.0, mean = 0.0;
  int n = 0;
  for (int i = 0; i < 40; ++i) {
    const float x = 0.137f * i, y = 0.071f * i + 0.3f;
    const float theta = 0.1f + 1.3f * float(i % 5) / 5.0f, phi = 0.7f * i;
    const V3f to_eye(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                     std::cos(theta));
    const ClothMaterial::Light light{V3f(0.3f, -0.4f, 0.866f).normalized(), V3f(1.0f, 0.8f, 0.6f)};
    for (float footprint : {1.0f, 3.0f}) {
      const V3f a = rgb.shade(x, y, footprint, to_eye, std::span(&light, 1)).radiance;
      const V3f b = parts.shade(x, y, footprint, to_eye, std::span(&light, 1)).radiance;
      worst = std::max(worst, double((a - b).length()));
      mean += a.length();
      ++n;
    }
  }
  mean /= n;
  ASSERT_GT(mean, 1e-3);
  EXPECT_LT(worst, 1e-4 * (1.0 + mean)) << "mean radiance " << mean;
}

// lookup-render's check: a scene whose cloth differs from a colour-free
// material's in colours only fits; any other difference is refused, naming
// the field under objects[i].cloth.
TEST(ColourFree, SceneCheckAcceptsOtherColoursAndNamesAnythingElse) {
  Scene scene;
  ClothObject obj;
  obj.mesh.positions_world = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  obj.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  obj.mesh.quads = {{{0, 1, 2, 3}, {0, 1, 2, 3}}};
  obj.cloth.resolution = {16, 16, 8, 1};
  obj.repeats_per_uv = 10.0f;
  scene.objects.push_back(obj);
  const ClothScene prepared(scene, k_budget);
  ClothMaterial m = unbaked_material(prepared.volume(0), object_optics(prepared, 0),
                                     tiny_settings(MaterialParts::SpecularWarpWeft));
  m.set_cloth(colour_free(obj.cloth), palette_of(obj.cloth));
  auto field_after = [&](auto change) -> std::string {
    Scene changed = scene;
    change(changed.objects[0].cloth);
    const ClothScene p(changed, k_budget);
    try {
      check_material_fits(p, 0, m);
    } catch (const InputError& e) {
      return e.field();
    }
    return "";
  };
  EXPECT_EQ(field_after([](ClothSpec&) {}), "");
  EXPECT_EQ(field_after([](ClothSpec& c) { c.weft.color = k_blue * 0.4f; }), "");
  // A 3-end stripe: a 6-end cloth, the same weave and cells per thread.
  EXPECT_EQ(field_after([](ClothSpec& c) { c.warp.colors = {k_red, k_green, k_blue}; }), "");
  EXPECT_EQ(field_after([](ClothSpec& c) { c.warp.spacing_mm = 0.55f; }),
            "objects[0].cloth.warp.spacing_mm");
  EXPECT_EQ(field_after([](ClothSpec& c) { c.crimp = 0.5f; }), "objects[0].cloth.crimp");
  EXPECT_EQ(field_after([](ClothSpec& c) { c.seed = 3; }), "objects[0].cloth.seed");
}

}  // namespace
}  // namespace clothbake
