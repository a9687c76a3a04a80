// Spot and area lights against closed forms.
//
// An area light is sampled: Light::illuminate at a uniform point of its
// shape gives I0 cos(theta_light) / d^2, whose mean over the shape is the
// irradiance of a Lambertian emitter of radiance L = I0 / area. On a
// Lambertian receiver that mean times the receiver's cosine has Lambert's
// closed form for a polygon (and sin^2 of the half-angle on a disk's axis);
// the tolerance is four standard errors of the estimate, measured from the
// samples themselves.

#include "core/scene/light.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace clothbake {
namespace {

using Imath::V3d;
using Imath::V3f;
constexpr double k_pi = std::numbers::pi;

V3d to_double(const V3f& v) { return V3d(v.x, v.y, v.z); }

/// Lambert's formula: irradiance at p (normal n) from a convex polygon of
/// uniform radiance L lying wholly above p's tangent plane.
double polygon_irradiance(const std::vector<V3d>& corners, const V3d& p, const V3d& n, double L) {
  double sum = 0.0;
  for (size_t i = 0; i < corners.size(); ++i) {
    const V3d a = (corners[i] - p).normalized();
    const V3d b = (corners[(i + 1) % corners.size()] - p).normalized();
    const V3d g = a.cross(b);
    const double gamma = std::atan2(g.length(), a.dot(b));
    sum += gamma * n.dot(g.normalized());
  }
  return 0.5 * L * std::fabs(sum);
}

struct Estimate {
  double mean = 0.0, standard_error = 0.0;
};

/// Mean over a side x side stratified grid of the light's irradiance on a
/// receiver with normal n (the receiver's cosine applied), channel 0.
Estimate sampled_irradiance(const Light& light, const V3f& p, const V3f& n, int side) {
  double sum = 0.0, sum_sq = 0.0;
  uint32_t state = 12345u;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      V3f to_light, irradiance;
      light.illuminate(p, to_light, irradiance, (i + next()) / side, (j + next()) / side);
      const double e = irradiance.x * std::max(0.0f, to_light.dot(n));
      sum += e;
      sum_sq += e * e;
    }
  const double count = double(side) * side;
  Estimate out;
  out.mean = sum / count;
  // The unstratified standard error bounds the stratified one.
  out.standard_error = std::sqrt(std::max(0.0, sum_sq / count - out.mean * out.mean) / count);
  return out;
}

Light rectangle_light() {
  Light light;
  light.type = LightType::Area;
  light.position_world = V3f(0.3f, -0.2f, 2.0f);
  light.axis_world = V3f(0, 0, -1);
  light.side_world = V3f(1, 0, 0);
  light.area_shape = AreaShape::Rectangle;
  light.area_width = 1.5f;
  light.area_height = 0.8f;
  light.intensity = 3.0f;
  return light;
}

TEST(AreaLight, RectangleMatchesLambertsFormula) {
  const Light light = rectangle_light();
  const double L = light.intensity / light.area();
  const V3d c = to_double(light.position_world), x = to_double(light.side_world) * 0.75,
            y = to_double(light.axis_world.cross(light.side_world)) * 0.4;
  const std::vector<V3d> corners = {c - x - y, c + x - y, c + x + y, c - x + y};
  struct Receiver {
    V3f p, n;
  };
  // Under the centre, under a corner, far to the side, and tilted.
  for (const Receiver r : {Receiver{{0.3f, -0.2f, 0}, {0, 0, 1}},
                           Receiver{{1.05f, 0.2f, 0}, {0, 0, 1}},
                           Receiver{{-2.5f, 1.0f, 0.5f}, {0, 0, 1}},
                           Receiver{{0, 0, 0}, V3f(0.3f, -0.2f, 1).normalized()}}) {
    const Estimate e = sampled_irradiance(light, r.p, r.n, 256);
    const double exact = polygon_irradiance(corners, to_double(r.p), to_double(r.n), L);
    EXPECT_GT(exact, 0.0);
    EXPECT_NEAR(e.mean, exact, 4.0 * e.standard_error + 1e-5 * exact)
        << "receiver at " << r.p << ", standard error " << e.standard_error;
  }
}

TEST(AreaLight, DiskOnItsAxisMatchesTheSolidAngle) {
  Light light = rectangle_light();
  light.area_shape = AreaShape::Ellipse;
  light.area_width = light.area_height = 1.2f;  // radius 0.6
  const double h = 2.0, r = 0.6;
  const double L = light.intensity / light.area();
  const double exact = L * k_pi * r * r / (r * r + h * h);  // L pi sin^2(half-angle)
  const Estimate e = sampled_irradiance(light, V3f(0.3f, -0.2f, 0), V3f(0, 0, 1), 256);
  EXPECT_NEAR(e.mean, exact, 4.0 * e.standard_error + 1e-5 * exact);
  EXPECT_NEAR(light.area(), k_pi * r * r, 1e-6);
  // An ellipse: every sample lies inside it.
  light.area_width = 2.0f;
  light.area_height = 0.5f;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      V3f to_light, irradiance;
      const V3f p(0.3f, -0.2f, 0.0f);
      light.illuminate(p, to_light, irradiance, (i + 0.5f) / 64, (j + 0.5f) / 64);
      // Where the ray to the sample meets the light's plane z = 2.
      const V3f hit = p + to_light * (2.0f / to_light.z) - light.position_world;
      const float ex = hit.x / 1.0f, ey = hit.y / 0.25f;
      ASSERT_LE(ex * ex + ey * ey, 1.0f + 1e-4f) << i << "," << j;
    }
}

TEST(AreaLight, IsOneSided) {
  const Light light = rectangle_light();  // shines down, along -z
  V3f to_light, irradiance;
  light.illuminate(V3f(0.3f, -0.2f, 5.0f), to_light, irradiance, 0.3f, 0.7f);
  EXPECT_EQ(irradiance, V3f(0, 0, 0));
  light.illuminate(V3f(0.3f, -0.2f, -5.0f), to_light, irradiance, 0.3f, 0.7f);
  EXPECT_GT(irradiance.x, 0.0f);
  // In its own plane: zero, never NaN.
  light.illuminate(V3f(5.0f, -0.2f, 2.0f), to_light, irradiance, 0.5f, 0.5f);
  EXPECT_EQ(irradiance, V3f(0, 0, 0));
  EXPECT_TRUE(std::isfinite(to_light.x) && std::isfinite(to_light.y) && std::isfinite(to_light.z));
}

// Far away an area light is a point light of intensity I0 cos(theta): the
// exact limit as its size goes to zero.
TEST(AreaLight, SmallLightIsAPointLightTimesCosine) {
  Light light = rectangle_light();
  light.area_width = light.area_height = 1e-4f;
  const V3f p(1.5f, 0.8f, -1.0f);
  const V3f offset = light.position_world - p;
  const float cos_light = offset.normalized().z;  // -(to_light . axis), axis = -z
  V3f to_light, irradiance;
  light.illuminate(p, to_light, irradiance, 0.9f, 0.1f);
  EXPECT_NEAR(irradiance.x, light.intensity * cos_light / offset.length2(), 1e-4 * irradiance.x);
  EXPECT_LT((to_light - offset.normalized()).length(), 1e-4f);
}

Light spot_light(float size_deg, float blend) {
  Light light;
  light.type = LightType::Spot;
  light.position_world = V3f(0, 0, 3);
  light.axis_world = V3f(0, 0, -1);
  const double half = 0.5 * size_deg * k_pi / 180.0;
  light.spot_cos_half_angle = float(std::cos(half));
  light.spot_smooth = float((1.0 - std::cos(half)) * blend);
  light.intensity = 9.0f;
  return light;
}

/// The point on z = 0 seen from the spot at `angle_deg` off its axis.
V3f ground_at(double angle_deg) {
  return V3f(float(3.0 * std::tan(angle_deg * k_pi / 180.0)), 0.0f, 0.0f);
}

TEST(SpotLight, IsAPointLightTimesCosineInsideTheCone) {
  const Light spot = spot_light(60.0f, 0.0f);
  for (double angle : {0.0, 10.0, 20.0, 29.9}) {
    const V3f p = ground_at(angle);
    const float d2 = (spot.position_world - p).length2();
    V3f to_light, irradiance;
    spot.illuminate(p, to_light, irradiance);
    const double expected = 9.0 * std::cos(angle * k_pi / 180.0) / d2;
    EXPECT_NEAR(irradiance.x, expected, 1e-5 * expected) << angle;
  }
  for (double angle : {30.1, 45.0, 80.0}) {
    V3f to_light, irradiance;
    spot.illuminate(ground_at(angle), to_light, irradiance);
    EXPECT_EQ(irradiance, V3f(0, 0, 0)) << angle;
  }
  // Behind the light.
  V3f to_light, irradiance;
  spot.illuminate(V3f(0, 0, 6), to_light, irradiance);
  EXPECT_EQ(irradiance, V3f(0, 0, 0));
}

TEST(SpotLight, BlendIsCyclesSmoothstepOnTheCosine) {
  const float c = float(std::cos(30.0 * k_pi / 180.0));
  const float smooth = (1.0f - c) * 0.4f;
  // Half-way through the band: smoothstep(0.5) = 0.5; the band's inner end: 1.
  EXPECT_NEAR(spot_attenuation(c + 0.5f * smooth, c, smooth, true), 0.5f * (c + 0.5f * smooth), 1e-6f);
  EXPECT_NEAR(spot_attenuation(c + smooth, c, smooth, true), c + smooth, 1e-6f);
  EXPECT_NEAR(spot_attenuation(c + 0.25f * smooth, c, smooth, true),
              (c + 0.25f * smooth) * 0.15625f, 1e-6f);  // 3/16 - 2/64
  EXPECT_EQ(spot_attenuation(c, c, smooth, true), 0.0f);
  EXPECT_EQ(spot_attenuation(1.0f, c, smooth, true), 1.0f);
  // Monotonic from the edge to the axis.
  float last = 0.0f;
  for (int i = 0; i <= 100; ++i) {
    const float a = spot_attenuation(c + (1.0f - c) * float(i) / 100.0f, c, smooth, true);
    EXPECT_GE(a, last);
    last = a;
  }
}

// Blender 4.0 and later: the same band without the cosine, so 1 anywhere
// inside it and the smoothstep alone across it; the two masks' ratio is
// the cosine everywhere in the cone.
TEST(SpotLight, WithoutTheAxisCosineTheMaskIsTheSmoothstepAlone) {
  const float c = float(std::cos(30.0 * k_pi / 180.0));
  const float smooth = (1.0f - c) * 0.4f;
  EXPECT_NEAR(spot_attenuation(c + 0.5f * smooth, c, smooth, false), 0.5f, 1e-6f);
  EXPECT_NEAR(spot_attenuation(c + 0.25f * smooth, c, smooth, false), 0.15625f, 1e-6f);
  EXPECT_EQ(spot_attenuation(c + smooth, c, smooth, false), 1.0f);
  EXPECT_EQ(spot_attenuation(c, c, smooth, false), 0.0f);
  for (int i = 1; i <= 100; ++i) {
    const float cos_axis = c + (1.0f - c) * float(i) / 100.0f;
    EXPECT_NEAR(spot_attenuation(cos_axis, c, smooth, true),
                cos_axis * spot_attenuation(cos_axis, c, smooth, false), 1e-6f);
  }
}

}  // namespace
}  // namespace clothbake
