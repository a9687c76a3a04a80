// Tests of the pinhole camera (baker/core/geometry/camera.h) and the lights
// (baker/core/scene/light.h).
//
// Angles are compared in double from float directions (relative error ~1e-7),
// so 1e-5 rad is a wide margin; a half-pixel offset or a focal length off by
// the aspect ratio misses it by orders.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/geometry/camera.h"
#include "core/scene/light.h"
#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V3d;
using Imath::V3f;

constexpr double kDeg = std::numbers::pi / 180.0;

double angle_between(const V3f& a, const V3f& b) {
  const V3d ad(a.x, a.y, a.z), bd(b.x, b.y, b.z);
  return std::atan2(ad.cross(bd).length(), ad.dot(bd));
}

PinholeCamera oblique_camera(FovAxis axis) {
  PinholeCamera cam;
  cam.position_world = V3f(1.0f, 2.0f, 3.0f);
  cam.look_at_world = V3f(-2.0f, 0.5f, 1.0f);
  cam.up_world = V3f(0.1f, 1.0f, 0.0f);
  cam.fov_deg = 37.0f;
  cam.fov_axis = axis;
  cam.width = 426;
  cam.height = 266;
  return cam;
}

TEST(Camera, CentreRayLooksForward) {
  const PinholeCamera cam = oblique_camera(FovAxis::Horizontal);
  const Ray ray = cam.generate_ray(0.5f * cam.width, 0.5f * cam.height);
  const V3f forward = (cam.look_at_world - cam.position_world).normalized();
  EXPECT_LT((ray.direction_world - forward).length(), 1e-6);
  EXPECT_EQ(ray.origin_world, cam.position_world);
  EXPECT_NEAR(ray.direction_world.length(), 1.0f, 1e-6);
}

TEST(Camera, FieldOfViewSpansTheStatedAxis) {
  for (FovAxis axis : {FovAxis::Horizontal, FovAxis::Vertical}) {
    const PinholeCamera cam = oblique_camera(axis);
    const float w = float(cam.width), h = float(cam.height);
    const double fov = cam.fov_deg * kDeg;
    const double across_width = angle_between(cam.generate_ray(0, 0.5f * h).direction_world,
                                              cam.generate_ray(w, 0.5f * h).direction_world);
    const double across_height = angle_between(cam.generate_ray(0.5f * w, 0).direction_world,
                                               cam.generate_ray(0.5f * w, h).direction_world);
    // Square pixels: one focal length for both axes.
    const double focal =
        axis == FovAxis::Horizontal ? 0.5 * w / std::tan(0.5 * fov) : 0.5 * h / std::tan(0.5 * fov);
    EXPECT_NEAR(across_width, 2.0 * std::atan(0.5 * w / focal), 1e-5);
    EXPECT_NEAR(across_height, 2.0 * std::atan(0.5 * h / focal), 1e-5);
    EXPECT_NEAR(axis == FovAxis::Horizontal ? across_width : across_height, fov, 1e-5);
    // The corner rays (0, 0) and (width, height) span the diagonal.
    const double diagonal = angle_between(cam.generate_ray(0, 0).direction_world,
                                          cam.generate_ray(w, h).direction_world);
    EXPECT_NEAR(diagonal, 2.0 * std::atan(0.5 * std::hypot(w, h) / focal), 1e-5);
  }
}

TEST(Camera, ProjectInvertsGenerateRay) {
  for (FovAxis axis : {FovAxis::Horizontal, FovAxis::Vertical}) {
    const PinholeCamera cam = oblique_camera(axis);
    Rng rng(9);
    for (int i = 0; i < 200; ++i) {
      // Include positions outside the image.
      const float x = (rng.next_float() * 1.4f - 0.2f) * cam.width;
      const float y = (rng.next_float() * 1.4f - 0.2f) * cam.height;
      const Ray ray = cam.generate_ray(x, y);
      float px = 0, py = 0;
      ASSERT_TRUE(cam.project(ray.origin_world + ray.direction_world * 3.0f, px, py));
      EXPECT_NEAR(px, x, 1e-3);
      EXPECT_NEAR(py, y, 1e-3);
    }
  }
}

TEST(Camera, ImageYGrowsDownwardAndXToTheRight) {
  PinholeCamera cam;  // at (0, 0, 5) looking at the origin, up +y
  float x = 0, y = 0;
  ASSERT_TRUE(cam.project(V3f(0, 0.5f, 0), x, y));
  EXPECT_LT(y, 0.5f * cam.height);
  EXPECT_NEAR(x, 0.5f * cam.width, 1e-3);
  ASSERT_TRUE(cam.project(V3f(0.5f, 0, 0), x, y));
  EXPECT_GT(x, 0.5f * cam.width);
  EXPECT_NEAR(y, 0.5f * cam.height, 1e-3);
  // Top-left pixel looks up and to the left.
  const Ray corner = cam.generate_ray(0, 0);
  EXPECT_LT(corner.direction_world.x, 0.0f);
  EXPECT_GT(corner.direction_world.y, 0.0f);
}

TEST(Camera, PointsBehindDoNotProject) {
  PinholeCamera cam;
  float x = -7, y = -7;
  EXPECT_FALSE(cam.project(V3f(0, 0, 6), x, y));        // behind
  EXPECT_FALSE(cam.project(V3f(1, 0.5f, 5), x, y));     // on the camera plane
  EXPECT_FALSE(cam.project(cam.position_world, x, y));  // the eye itself
  EXPECT_EQ(x, -7);
  EXPECT_EQ(y, -7);
}

TEST(Camera, DegenerateSetupsStayFinite) {
  PinholeCamera same;
  same.look_at_world = same.position_world;
  PinholeCamera parallel_up;
  parallel_up.up_world = V3f(0, 0, -3);  // along the view direction
  PinholeCamera zero_up;
  zero_up.up_world = V3f(0, 0, 0);
  for (const PinholeCamera& cam : {same, parallel_up, zero_up}) {
    for (const auto& [x, y] :
         {std::pair{0.0f, 0.0f}, std::pair{213.0f, 133.0f}, std::pair{426.0f, 266.0f}}) {
      const V3f d = cam.generate_ray(x, y).direction_world;
      EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z));
      EXPECT_NEAR(d.length(), 1.0f, 1e-6);
    }
  }
  // With only up degenerate, the view direction is still honoured.
  EXPECT_LT((parallel_up.generate_ray(213, 133).direction_world - V3f(0, 0, -1)).length(), 1e-6);
}

TEST(Light, PointLightFollowsInverseSquare) {
  Light light;
  light.type = LightType::Point;
  light.position_world = V3f(1, 2, 3);
  light.color = V3f(0.5f, 1.0f, 2.0f);
  light.intensity = 5.0f;
  // Offsets along a 3-4-5 direction keep every distance exact in float.
  const V3f dir(0.6f, 0.8f, 0.0f);
  for (float k : {0.25f, 1.0f, 2.0f, 7.5f}) {
    const float dist = 5.0f * k;
    V3f to_light, irradiance;
    light.illuminate(light.position_world - V3f(3.0f * k, 4.0f * k, 0.0f), to_light, irradiance);
    EXPECT_LT((to_light - dir).length(), 1e-6);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(irradiance[c], light.color[c] * light.intensity / (dist * dist),
                  1e-6 * irradiance[c]);
  }
  // Doubling the distance quarters the irradiance.
  V3f to_light, near_e, far_e;
  light.illuminate(light.position_world - V3f(1.5f, 2.0f, 0.0f), to_light, near_e);
  light.illuminate(light.position_world - V3f(3.0f, 4.0f, 0.0f), to_light, far_e);
  EXPECT_NEAR(far_e.y * 4.0f, near_e.y, 1e-6 * near_e.y);

  // At the light itself: zero irradiance, a finite unit direction.
  light.illuminate(light.position_world, to_light, near_e);
  EXPECT_EQ(near_e, V3f(0, 0, 0));
  EXPECT_NEAR(to_light.length(), 1.0f, 1e-6);
}

TEST(Light, DirectionalNormalises) {
  Light light;
  light.type = LightType::Directional;
  light.to_light_world = V3f(0, 3, 4);
  light.color = V3f(1.0f, 0.5f, 0.25f);
  light.intensity = 2.0f;
  for (const V3f& p : {V3f(0, 0, 0), V3f(100, -50, 3)}) {
    V3f to_light, irradiance;
    light.illuminate(p, to_light, irradiance);
    EXPECT_LT((to_light - V3f(0, 0.6f, 0.8f)).length(), 1e-6);
    EXPECT_EQ(irradiance, V3f(2.0f, 1.0f, 0.5f));
  }
  light.to_light_world = V3f(0, 0, 0);
  V3f to_light, irradiance;
  light.illuminate(V3f(1, 1, 1), to_light, irradiance);
  EXPECT_EQ(irradiance, V3f(0, 0, 0));
  EXPECT_TRUE(std::isfinite(to_light.x) && std::isfinite(to_light.y) && std::isfinite(to_light.z));
}

}  // namespace
}  // namespace clothbake
