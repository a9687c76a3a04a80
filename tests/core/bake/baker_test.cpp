#include "core/bake/baker.h"

#include <cmath>
#include <cstring>
#include <numbers>
#include <tuple>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/texture/volume_generator.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr uint64_t k_budget = uint64_t(1) << 32;

/// The homogeneous isotropic slab of renderer_test.cpp: radiance known in
/// closed form for every view direction (docs/design/slab-analytic.md).
Scene slab_scene() {
  Scene scene;
  ClothObject obj;
  obj.mesh.positions_world = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  obj.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  obj.mesh.quads = {{{0, 1, 2, 3}, {0, 1, 2, 3}}};
  obj.cloth.pattern = k_uniform_pattern;
  obj.cloth.density.core = 0.5f;
  obj.cloth.resolution = {8, 8, 16, 1};
  obj.repeats_per_uv = 10.0f;
  const WeaveGeometry g = weave_geometry(obj.cloth);
  obj.thickness_world = g.size_mm.z * 2.0f / (obj.repeats_per_uv * g.size_mm.x);
  obj.extinction_per_mm = 10.0f;
  obj.isotropic_albedo = V3f(0.8f);
  scene.objects.push_back(obj);
  scene.camera.position_world = V3f(0.3f, -0.2f, 6.0f);
  scene.camera.look_at_world = V3f(0, 0, 0);
  scene.camera.fov_deg = 15.0f;
  scene.camera.width = scene.camera.height = 32;
  Light light;
  light.to_light_world = V3f(0.5f, 0.2f, 0.8f).normalized();
  light.intensity = 2.0f;
  scene.lights = {light};
  scene.settings.shading = ShadingMode::Isotropic;
  scene.settings.step_cells = 0.1f;
  scene.settings.cutoff = 1e-5f;
  return scene;
}

double slab_radiance(double mu_v, double mu_l, double tau0) {
  const double p = 1.0 / (4.0 * std::numbers::pi);
  return 0.8 * p * 2.0 * mu_l / (mu_l + mu_v) * (1.0 - std::exp(-tau0 * (1.0 / mu_v + 1.0 / mu_l)));
}

TEST(HemiOct, EncodeDecodeRoundTripAndNodesCoverTheHorizon) {
  for (int i = 0; i < 200; ++i) {
    const float a = 0.031f * i, z = 0.005f * i;
    const V3f d = V3f(std::cos(a), std::sin(a), z).normalized();
    const V3f back = hemi_oct_decode(hemi_oct_encode(d));
    EXPECT_NEAR((back - d).length(), 0.0f, 1e-5f);
  }
  DirectionGrid g;
  g.k = 5;
  g.map = DirectionMap::HemiOctahedral;
  EXPECT_NEAR(g.node_direction(0, 2, 2).z, 1.0f, 1e-6f);   // centre node: the normal
  EXPECT_NEAR(g.node_direction(0, 0, 2).z, 0.0f, 1e-6f);   // border nodes: the horizon
  EXPECT_NEAR(g.node_direction(1, 2, 2).z, -1.0f, 1e-6f);  // back side mirrored
  const DirectionGrid::Footprint f = g.locate(g.node_direction(0, 3, 1));
  EXPECT_EQ(f.side, 0);
  EXPECT_NEAR(f.i0 + f.fx, 3.0f, 1e-5f);
  EXPECT_NEAR(f.j0 + f.fy, 1.0f, 1e-5f);
}

// At node directions the lookup reproduces the march (the analytic slab
// within 1%: 16 sub-texel samples of a march whose per-ray jitter noise is
// ~1%); between nodes the error is the bilinear interpolation of a smooth
// function of direction, bounded here by 3% at K = 9 on the polar map (the
// slab's radiance depends on elevation only, which polar rows follow
// exactly; tests/core/geometry/direction_grid_test.cpp measures both maps).
TEST(PolarMap, NodesAndFootprintsWrapInAzimuth) {
  DirectionGrid g;
  g.k = 8;
  g.map = DirectionMap::Polar;
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(g.node_direction(0, i, 0).z, 1.0f, 1e-6f);  // the pole
  EXPECT_NEAR(g.node_direction(0, 3, 7).z, 0.0f, 1e-6f);                              // horizon
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const DirectionGrid::Footprint f = g.locate(g.node_direction(0, i, j));
      EXPECT_NEAR(f.j0 + f.fy, float(j), 1e-4f);
      if (j > 0) EXPECT_NEAR(std::fmod(f.i0 + f.fx, 8.0f), float(i), 1e-4f);
    }
  // Just below azimuth 2 pi: between the last node and node 0.
  const DirectionGrid::Footprint f = g.locate(V3f(std::cos(-0.1f), std::sin(-0.1f), 0.5f));
  EXPECT_EQ(f.i0, 7);
  EXPECT_EQ(f.i1, 0);
  EXPECT_EQ(g.locate(V3f(0.3f, 0.2f, -0.9f)).side, 1);
}

TEST(Baker, FullBakeOfTheSlabMatchesTheClosedForm) {
  Scene scene = slab_scene();
  ClothScene prepared(scene, k_budget);
  BakeSettings s;
  s.directions = 9;
  s.map = DirectionMap::Polar;
  s.texels = 2;
  s.spp = 16;
  const BakePlan plan = plan_bake(prepared, s);
  ASSERT_EQ(plan.baked_nodes, plan.full_nodes);
  const std::vector<LookupTable> tables = run_bake(prepared, plan, s);
  const double tau0 = 10.0 * 0.5 * prepared.volume(0).size_mm().z;
  const double mu_l = scene.lights[0].to_light_world.z;
  const LookupTable& t = tables[0];
  for (int j = 1; j < 8; ++j)
    for (int i = 1; i < 8; ++i) {
      const V3f d = t.dirs.node_direction(0, i, j);
      if (d.z < 0.2f) continue;
      float rgba[4];
      ASSERT_TRUE(t.sample(0, 0.5f, 0.5f, d, rgba));
      const double expected = slab_radiance(d.z, mu_l, tau0);
      EXPECT_NEAR(rgba[0], expected, 0.01 * expected) << "node " << i << "," << j;
      EXPECT_NEAR(rgba[3], 1.0 - std::exp(-tau0 / d.z), 0.01);
    }
  for (int n = 0; n < 50; ++n) {
    const float a = 0.37f * n, z = 0.3f + 0.014f * n;
    const V3f d = V3f(std::sqrt(1 - z * z) * std::cos(a), std::sqrt(1 - z * z) * std::sin(a), z);
    float rgba[4];
    ASSERT_TRUE(t.sample(0, 0.3f, 0.6f, d, rgba));
    const double expected = slab_radiance(d.z, mu_l, tau0);
    EXPECT_NEAR(rgba[0], expected, 0.03 * expected) << "direction z " << z;
  }
}

TEST(Baker, AdaptivePlanBakesOnlyWhatTheCameraSees) {
  const Scene scene = slab_scene();
  ClothScene prepared(scene, k_budget);
  BakeSettings s;
  s.directions = 16;
  s.adaptive = true;
  const BakePlan plan = plan_bake(prepared, s);
  const LookupTable& t = plan.objects[0];
  int front = 0, back = 0;
  for (int n = 0; n < t.node_count(); ++n)
    (n < t.dirs.nodes_per_side() ? front : back) += t.is_baked(0, n);
  EXPECT_EQ(back, 0);  // the camera is above the slab
  EXPECT_GE(front, 4);
  // A view cone of 15 degrees around the normal covers the first two polar
  // rings (every azimuth: 2 K = 32 nodes) and the pole row (K = 16, one
  // direction) at most: 48 of 256.
  EXPECT_LE(front, 48);
  // The quad spans the 32-pixel image (and beyond): about 1.5 texels per pixel.
  EXPECT_GE(t.sizes[0], 40);
  // Packed: only the baked nodes' squares are stored, so the front atlas
  // holds `front` squares (plus gutters), not K^2.
  EXPECT_LE(int64_t(t.atlases[0].width) * t.atlases[0].height,
            int64_t(front) * (t.sizes[0] + 2) * (t.sizes[0] + 2) * 2);
  EXPECT_EQ(t.atlases[1].width, 0);
  EXPECT_LT(plan.texel_direction_samples, plan.full_texel_direction_samples);
}

/// The slab split in a 2 x 2 grid of quads, shaded with the fibre model.
Scene four_quad_slab() {
  Scene scene = slab_scene();
  ClothObject& obj = scene.objects[0];
  obj.mesh.positions_world.clear();
  obj.mesh.uvs.clear();
  obj.mesh.quads.clear();
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      obj.mesh.positions_world.push_back(V3f(x - 1.0f, y - 1.0f, 0.0f));
      obj.mesh.uvs.push_back(Imath::V2f(x / 2.0f, y / 2.0f));
    }
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      const int a = y * 3 + x;
      obj.mesh.quads.push_back({{a, a + 1, a + 4, a + 3}, {a, a + 1, a + 4, a + 3}});
    }
  scene.settings.shading = ShadingMode::Fiber;
  return scene;
}

/// K = 3, 4 texels, 2 samples: a bake of the four-quad slab in milliseconds.
BakeSettings small_bake() {
  BakeSettings s;
  s.directions = 3;
  s.texels = 4;
  s.spp = 2;
  return s;
}

TEST(Baker, QuadSubsetsShareTheLayoutAndSameBytesForAnyThreadCount) {
  const Scene scene = four_quad_slab();
  ClothScene prepared(scene, k_budget);
  BakeSettings s = small_bake();
  const BakePlan whole = plan_bake(prepared, s);
  s.quad_begin = 1;
  s.quad_end = 3;
  const BakePlan part = plan_bake(prepared, s);
  ASSERT_EQ(whole.objects[0].atlases[0].width, part.objects[0].atlases[0].width);
  ASSERT_EQ(whole.objects[0].atlases[1].height, part.objects[0].atlases[1].height);
  for (size_t i = 0; i < whole.objects[0].slots.size(); ++i)
    EXPECT_EQ(whole.objects[0].slots[i].x, part.objects[0].slots[i].x);
  for (int q = 0; q < 4; ++q) EXPECT_EQ(part.objects[0].quad_baked(q), q == 1 || q == 2);
  std::vector<LookupTable> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = run_bake(prepared, part, s);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = run_bake(prepared, part, s);
  }
  for (int side = 0; side < 2; ++side) {
    const std::vector<Imath::half>&a = one[0].atlases[side].pixels,
          &b = two[0].atlases[side].pixels;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Imath::half)));
  }
}

/// A probe sample's place in the plan's sequence (object 0): quad, node,
/// texel row, texel, sample, as probe_samples orders them.
std::tuple<int, int, int, int, int> sequence_key(const BakeSample& x) {
  return {x.quad, x.node, x.b, x.a, x.k};
}

// The probe behind `bake --estimate` draws the number of samples asked for,
// distinct, valid, the same each time, spread over every quad and both sides;
// asked for more than the plan holds, it draws each planned sample once.
TEST(BakeProbe, DrawsTheRequestedSamplesSpreadOverThePlan) {
  const Scene scene = four_quad_slab();
  ClothScene prepared(scene, k_budget);
  BakeSettings s = small_bake();
  const BakePlan plan = plan_bake(prepared, s);
  ASSERT_EQ(plan.texel_direction_samples, 4u * 18u * 16u * 2u);
  const std::vector<BakeSample> probe = probe_samples(plan, s, 500);
  ASSERT_EQ(probe.size(), 500u);
  EXPECT_EQ(probe_bake(prepared, plan, s, 500), 500u);
  int per_quad[4] = {0, 0, 0, 0}, per_side[2] = {0, 0};
  const LookupTable& t = plan.objects[0];
  for (size_t i = 0; i < probe.size(); ++i) {
    const BakeSample& x = probe[i];
    ASSERT_TRUE(x.object == 0 && x.quad >= 0 && x.quad < 4 && t.is_baked(x.quad, x.node));
    ASSERT_TRUE(x.a >= 0 && x.a < 4 && x.b >= 0 && x.b < 4 && x.k >= 0 && x.k < 2);
    if (i > 0) EXPECT_LT(sequence_key(probe[i - 1]), sequence_key(x)) << "sample " << i;
    ++per_quad[x.quad];
    ++per_side[t.side_of(x.node)];
  }
  for (int q = 0; q < 4; ++q) EXPECT_EQ(per_quad[q], 125) << "quad " << q;  // equal shares
  EXPECT_NEAR(per_side[0], 250, 4);  // half the nodes are on the back
  const std::vector<BakeSample> again = probe_samples(plan, s, 500);
  for (size_t i = 0; i < probe.size(); ++i)
    EXPECT_EQ(sequence_key(again[i]), sequence_key(probe[i]));
  const std::vector<BakeSample> all = probe_samples(plan, s, 1u << 20);
  ASSERT_EQ(all.size(), plan.texel_direction_samples);
  for (size_t i = 1; i < all.size(); ++i) ASSERT_LT(sequence_key(all[i - 1]), sequence_key(all[i]));
}

// The probe times the bake's own work: each probe sample is exactly what
// run_bake stores for that texel at 1 sample per texel.
TEST(BakeProbe, EvaluatesWhatRunBakeStores) {
  const Scene scene = four_quad_slab();
  ClothScene prepared(scene, k_budget);
  BakeSettings s;
  s.directions = 3;
  s.texels = 4;
  s.spp = 1;
  const BakePlan plan = plan_bake(prepared, s);
  const std::vector<LookupTable> tables = run_bake(prepared, plan, s);
  const std::vector<BakeSample> probe = probe_samples(plan, s, 200);
  const std::vector<MarchResult> got = evaluate_bake_samples(prepared, plan, s, probe);
  ASSERT_EQ(got.size(), probe.size());
  int lit = 0;
  for (size_t i = 0; i < probe.size(); ++i) {
    const BakeSample& x = probe[i];
    const Imath::half* texel = tables[0].texel(x.quad, x.node, x.a, x.b);
    EXPECT_EQ(texel[0].bits(), Imath::half(got[i].radiance.x).bits()) << "sample " << i;
    EXPECT_EQ(texel[3].bits(), Imath::half(1.0f - got[i].transmittance).bits()) << "sample " << i;
    lit += got[i].radiance.x > 0.0f;
  }
  EXPECT_GT(lit, 50);  // not a comparison of zeros
}

// Nothing planned, nothing probed: a camera that sees no quad, or n = 0.
TEST(BakeProbe, NoPlannedWorkGivesNoSamples) {
  Scene scene = four_quad_slab();
  scene.camera.look_at_world = V3f(0.3f, -0.2f, 12.0f);  // away from the slab
  ClothScene prepared(scene, k_budget);
  BakeSettings s;
  s.adaptive = true;
  const BakePlan plan = plan_bake(prepared, s);
  ASSERT_EQ(plan.texel_direction_samples, 0u);
  EXPECT_EQ(probe_bake(prepared, plan, s, 1000), 0u);
  EXPECT_TRUE(probe_samples(plan, s, 1000).empty());
  s.adaptive = false;
  EXPECT_EQ(probe_bake(prepared, plan_bake(prepared, s), s, 0), 0u);
}

}  // namespace
}  // namespace clothbake
