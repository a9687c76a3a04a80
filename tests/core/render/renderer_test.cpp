#include "core/render/renderer.h"

#include <cmath>
#include <cstring>
#include <numbers>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/texture/volume_generator.h"
#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V3d;
using Imath::V3f;
constexpr double k_pi = std::numbers::pi;
constexpr uint64_t k_budget = uint64_t(1) << 32;

/// A flat 2 x 2 quad in z = 0 (normal +z), UVs [0,1]^2, over a volume whose
/// texture space is isotropic (the same mm per world unit in x, y and z).
Scene slab_scene(float density, float extinction, int layers) {
  Scene scene;
  ClothObject obj;
  obj.name = "slab";
  obj.mesh.positions_world = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  obj.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  obj.mesh.quads = {{{0, 1, 2, 3}, {0, 1, 2, 3}}};
  obj.cloth.pattern = k_uniform_pattern;
  obj.cloth.density.core = density;
  obj.cloth.resolution = {8, 8, layers, 1};
  obj.repeats_per_uv = 10.0f;  // 1 mm repeat -> 0.2 world units per mm
  const WeaveGeometry g = weave_geometry(obj.cloth);
  obj.thickness_world = g.size_mm.z * 2.0f / (obj.repeats_per_uv * g.size_mm.x);
  obj.extinction_per_mm = extinction;
  obj.isotropic_albedo = V3f(0.8f, 0.5f, 0.2f);
  scene.objects.push_back(obj);
  scene.camera.position_world = V3f(0, 0, 10);
  scene.camera.look_at_world = V3f(0, 0, 0);
  scene.camera.fov_deg = 10.0f;
  scene.camera.width = scene.camera.height = 16;
  scene.settings.shading = ShadingMode::Isotropic;
  scene.settings.step_cells = 0.05f;
  scene.settings.cutoff = 1e-6f;
  scene.settings.light_roulette = 0.0f;  // exact tests; LightRouletteIsUnbiased tests it
  return scene;
}

V3d to_double(const V3f& v) { return V3d(v.x, v.y, v.z); }

V3f direction(double theta_deg, double phi_deg) {
  const double t = theta_deg * k_pi / 180.0, p = phi_deg * k_pi / 180.0;
  return V3f(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)),
             float(std::cos(t)));
}

/// Single scattering from a homogeneous slab of optical depth tau0, isotropic
/// phase 1/(4 pi), albedo a, irradiance E from direction mu_l (> 0: the lit
/// side is the viewed side, < 0: lit from behind), seen at mu_v > 0
/// (docs/design/slab-analytic.md).
double slab_radiance(double a, double E, double tau0, double mu_v, double mu_l) {
  const double p = 1.0 / (4.0 * k_pi);
  if (mu_l > 0)
    return a * p * E * mu_l / (mu_l + mu_v) * (1.0 - std::exp(-tau0 * (1.0 / mu_v + 1.0 / mu_l)));
  const double m = -mu_l;
  return a * p * E * m / (m - mu_v) * (std::exp(-tau0 / m) - std::exp(-tau0 / mu_v));
}

struct SlabCase {
  double view_theta, view_phi, light_theta, light_phi;
};

class SlabAnalytic : public ::testing::TestWithParam<TransmittanceMode> {};

// The march converges to the analytic single-scattering radiance of a slab:
// within 0.5% at step = 0.05 cell (the discretisation bias is O((kappa dt)^2)
// ~ 1e-4 here; the march jitter is averaged over 32 rays).
TEST_P(SlabAnalytic, MatchesSingleScattering) {
  const float density = 0.5f, sigma = 10.0f;
  Scene scene = slab_scene(density, sigma, 16);
  scene.settings.transmittance = GetParam();
  for (const SlabCase c : {SlabCase{0, 0, 45, 0}, SlabCase{30, 0, 45, 180}, SlabCase{60, 90, 20, 0},
                           SlabCase{45, 45, 70, 200}, SlabCase{75, 0, 10, 0},
                           SlabCase{30, 0, 135, 0}, SlabCase{10, 0, 160, 90}}) {
    Light light;
    light.type = LightType::Directional;
    light.to_light_world = direction(c.light_theta, c.light_phi);
    light.intensity = 2.0f;
    scene.lights = {light};
    Renderer renderer(scene, k_budget);
    renderer.prepared().prepare_light_caches();
    const V3f to_eye = direction(c.view_theta, c.view_phi);
    const double tau0 = double(sigma) * density * renderer.prepared().volume(0).size_mm().z;
    const double mu_v = to_eye.z, mu_l = light.to_light_world.z;
    V3f sum(0.0f);
    double see_through = 0.0;
    const int n = 32;
    for (int i = 0; i < n; ++i) {
      const Ray ray{to_eye * 5.0f + V3f(0.01f * i, -0.007f * i, 0), -to_eye};
      const TraceResult r = renderer.trace(ray, hash_key(7, i));
      sum += r.radiance;
      see_through += r.transmittance;
    }
    for (int ch = 0; ch < 3; ++ch) {
      const double expected =
          slab_radiance(scene.objects[0].isotropic_albedo[ch], light.intensity, tau0, mu_v, mu_l);
      EXPECT_NEAR(sum[ch] / n, expected, 0.005 * expected)
          << "view " << c.view_theta << "/" << c.view_phi << " light " << c.light_theta << "/"
          << c.light_phi << " channel " << ch;
    }
    EXPECT_NEAR(see_through / n, std::exp(-tau0 / mu_v), 0.005 * std::exp(-tau0 / mu_v) + 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(BothTransmittanceModes, SlabAnalytic,
                         ::testing::Values(TransmittanceMode::ShadowMarch,
                                           TransmittanceMode::Cached));

// An area light over the slab: the march, with one light point drawn per
// ray, converges to the analytic slab radiance integrated over the light
// (a 200 x 200 midpoint quadrature of I0 cos / d^2 over the rectangle, or
// over the disk). The tolerance is 4 standard errors measured from the rays
// plus the march's 0.5% bound. Lit from the front, from behind (light
// through the cloth), and with the slab behind the light (zero).
TEST(Renderer, AreaLightMatchesTheSlabIntegratedOverTheLight) {
  const float density = 0.5f, sigma = 10.0f;
  Scene scene = slab_scene(density, sigma, 16);
  scene.settings.step_cells = 0.1f;
  struct Case {
    V3f centre, normal;
    AreaShape shape;
  };
  for (const Case c : {Case{{0.8f, 0.3f, 1.2f}, {-0.5f, -0.2f, -1.0f}, AreaShape::Rectangle},
                       Case{{-0.4f, 0.2f, -1.5f}, {0.2f, -0.1f, 1.0f}, AreaShape::Ellipse},
                       Case{{0.0f, 0.0f, -1.0f}, {0.0f, 0.0f, -1.0f}, AreaShape::Rectangle}}) {
    Light light;
    light.type = LightType::Area;
    light.position_world = c.centre;
    light.axis_world = c.normal.normalized();
    light.side_world = V3f(0, 1, 0).cross(light.axis_world).normalized();
    light.area_shape = c.shape;
    light.area_width = 1.2f;
    light.area_height = 0.7f;
    light.intensity = 2.0f;
    scene.lights = {light};
    Renderer renderer(scene, k_budget);
    renderer.prepared().prepare_light_caches();
    const V3f to_eye = direction(35, 60);
    const double tau0 = double(sigma) * density * renderer.prepared().volume(0).size_mm().z;
    const double a = scene.objects[0].isotropic_albedo[0];
    // The analytic value, by quadrature over the light (independent of its sampler).
    const V3d up = to_double(light.axis_world.cross(light.side_world));
    double expected = 0.0;
    const int side = 200;
    int inside = 0;
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j) {
        const double x = (i + 0.5) / side - 0.5, y = (j + 0.5) / side - 0.5;
        if (c.shape == AreaShape::Ellipse && x * x + y * y > 0.25) continue;
        ++inside;
        const V3d point = to_double(light.position_world) +
                          to_double(light.side_world) * (x * light.area_width) +
                          up * (y * light.area_height);
        const double d2 = point.length2(), d = std::sqrt(d2);
        const V3d to_light = point / d;  // from the origin, where the rays aim
        const double cos_light = -to_light.dot(to_double(light.axis_world));
        if (cos_light <= 0.0) continue;
        expected += slab_radiance(a, light.intensity * cos_light / d2, tau0, to_eye.z, to_light.z);
      }
    expected /= inside;
    const int n = 4000;
    double sum = 0.0, sum_sq = 0.0;
    for (int i = 0; i < n; ++i) {
      const Ray ray{to_eye * 5.0f, -to_eye};
      const double r = renderer.trace(ray, hash_key(13, i)).radiance.x;
      sum += r;
      sum_sq += r * r;
    }
    const double mean = sum / n;
    const double standard_error = std::sqrt(std::max(0.0, sum_sq / n - mean * mean) / n);
    EXPECT_NEAR(mean, expected, 4.0 * standard_error + 0.005 * expected)
        << "light at " << c.centre << ", standard error " << standard_error;
    if (c.centre.z == -1.0f) EXPECT_EQ(expected, 0.0);  // the slab is behind the light
  }
}

TEST(Renderer, ZeroDensityRendersTheBackground) {
  Scene scene = slab_scene(0.5f, 10.0f, 4);
  scene.background = V3f(0.2f, 0.3f, 0.4f);
  scene.lights = {Light{}};
  scene.settings.spp = 4;
  auto empty = std::make_shared<VolumeTexture>(generate_volume(scene.objects[0].cloth, k_budget));
  for (size_t i = 0; i < empty->cell_count(); ++i)
    empty->at(int(i % empty->nx()), int(i / empty->nx() % empty->ny()),
              int(i / (empty->nx() * empty->ny()))) = Cell{};
  Renderer renderer(scene, k_budget, {empty});
  const Image img = renderer.render();
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = img.at(x, y);
      ASSERT_FLOAT_EQ(p[0], 0.2f);
      ASSERT_FLOAT_EQ(p[1], 0.3f);
      ASSERT_FLOAT_EQ(p[2], 0.4f);
      ASSERT_FLOAT_EQ(p[3], 0.0f);
    }
}

TEST(Renderer, OpaqueDensityGivesAlphaOne) {
  Scene scene = slab_scene(1.0f, 1000.0f, 4);  // optical depth 360: nothing gets through
  scene.lights = {Light{}};
  scene.settings.spp = 4;
  scene.settings.step_cells = 0.5f;
  scene.settings.cutoff = 1e-3f;
  Renderer renderer(scene, k_budget);
  const Image img = renderer.render();
  // The 2 x 2 quad fills the 10 degree view from 10 units (1.75 units wide).
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) ASSERT_EQ(img.at(x, y)[3], 1.0f) << x << "," << y;
}

// Russian roulette on the light (settings.light_roulette) skips most shadow
// marches behind a dim view but weights the rest so the expectation is
// unchanged. At its most aggressive (1: every sample's lights at probability
// = view transmittance), the mean of many rays must still match the analytic
// slab; the tolerance is 4 standard errors of that mean, measured from the
// rays themselves, plus the march's own 0.5% bound. With roulette off the
// same rays have far less spread: the test would see a biased weighting.
TEST(Renderer, LightRouletteIsUnbiased) {
  const float density = 0.5f, sigma = 10.0f;
  Scene scene = slab_scene(density, sigma, 16);
  scene.settings.step_cells = 0.25f;
  scene.settings.light_roulette = 1.0f;
  Light light;
  light.type = LightType::Directional;
  light.to_light_world = direction(45, 0);
  light.intensity = 2.0f;
  scene.lights = {light};
  Renderer renderer(scene, k_budget);
  const V3f to_eye = direction(30, 90);
  const double tau0 = double(sigma) * density * renderer.prepared().volume(0).size_mm().z;
  const double expected = slab_radiance(scene.objects[0].isotropic_albedo[0], light.intensity, tau0,
                                        to_eye.z, light.to_light_world.z);
  const int n = 20000;
  double sum = 0.0, sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    // Rays spread over the middle of the quad, away from its edges.
    const V3f offset(0.8f * float(i % 97) / 97.0f - 0.4f, 0.8f * float(i % 89) / 89.0f - 0.4f, 0);
    const Ray ray{to_eye * 5.0f + offset, -to_eye};
    const double r = renderer.trace(ray, hash_key(11, i)).radiance.x;
    sum += r;
    sum_sq += r * r;
  }
  const double mean = sum / n, variance = sum_sq / n - mean * mean;
  const double standard_error = std::sqrt(variance / n);
  EXPECT_GT(standard_error, 1e-4 * expected);  // the roulette does act
  EXPECT_NEAR(mean, expected, 4.0 * standard_error + 0.005 * expected)
      << "standard error " << standard_error;
}

Scene woven_scene() {
  Scene scene = slab_scene(0.5f, 40.0f, 12);
  ClothObject& obj = scene.objects[0];
  obj.cloth = ClothSpec{};
  obj.cloth.resolution = {32, 32, 12, 2};
  const WeaveGeometry g = weave_geometry(obj.cloth);
  obj.repeats_per_uv = 6.0f;
  obj.thickness_world = g.size_mm.z * 2.0f / (obj.repeats_per_uv * g.size_mm.x);
  scene.settings.shading = ShadingMode::Fiber;
  scene.settings.step_cells = 0.5f;
  scene.settings.cutoff = 1e-3f;
  scene.settings.spp = 2;
  scene.camera.position_world = V3f(0.0f, -6.0f, 8.0f);
  scene.camera.fov_deg = 12.0f;
  scene.camera.width = scene.camera.height = 48;
  Light key;
  key.to_light_world = direction(40, 120);
  key.intensity = 3.0f;
  Light fill;
  fill.type = LightType::Point;
  fill.position_world = V3f(3, 2, 2);
  fill.intensity = 8.0f;
  scene.lights = {key, fill};
  return scene;
}

double rmse(const Image& a, const Image& b) {
  double s = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    if (i % 4 != 3) s += (a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
  return std::sqrt(s / (a.pixels.size() * 3 / 4));
}

// The cached light transmittance changes nothing but the light reaching each
// sample; its difference from the per-sample shadow march (same seed, so the
// same samples) must be below the image's own sampling noise, estimated from
// two seeds of the shadow march: RMSE(seed a, seed b) / sqrt(2).
TEST(Renderer, CachedTransmittanceAgreesWithShadowMarchWithinNoise) {
  Scene scene = woven_scene();
  scene.settings.transmittance = TransmittanceMode::ShadowMarch;
  const Image shadow_a = Renderer(scene, k_budget).render();
  scene.settings.seed = 2;
  const Image shadow_b = Renderer(scene, k_budget).render();
  scene.settings.seed = 1;
  scene.settings.transmittance = TransmittanceMode::Cached;
  const Image cached_a = Renderer(scene, k_budget).render();
  const double noise = rmse(shadow_a, shadow_b) / std::sqrt(2.0);
  const double bias = rmse(shadow_a, cached_a);
  EXPECT_GT(noise, 0.0);
  EXPECT_LT(bias, noise) << "bias " << bias << " noise " << noise;
}

TEST(Renderer, SameBytesForAnyThreadCount) {
  const Scene scene = woven_scene();
  Image one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = Renderer(scene, k_budget).render();
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = Renderer(scene, k_budget).render();
  }
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(0,
            std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)));
}

}  // namespace
}  // namespace clothbake
