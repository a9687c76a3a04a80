// Lights: the direction toward a light and the irradiance it delivers.
//
// Degenerate lights never produce NaN: a zero (or non-finite) directional
// vector, or a surface point at a point light's position, gives zero
// irradiance and the placeholder direction +z.

#include "core/scene/light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clothbake {

namespace {
using Imath::V3f;

/// Shirley and Chiu's concentric map of the unit square onto the unit disk:
/// uniform, and strata stay compact (so stratified samples stay stratified).
void concentric_disk(float u1, float u2, float& x, float& y) {
  const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
  if (a == 0.0f && b == 0.0f) {
    x = y = 0.0f;
    return;
  }
  constexpr float quarter = 0.25f * std::numbers::pi_v<float>;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = quarter * (b / a);
  } else {
    r = b;
    phi = 2.0f * quarter - quarter * (a / b);
  }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}
}  // namespace

float spot_attenuation(float cos_axis, float cos_half_angle, float smooth, bool axis_cosine) {
  if (!(cos_axis > cos_half_angle)) return 0.0f;
  const float inside = axis_cosine ? cos_axis : 1.0f;
  const float t = cos_axis - cos_half_angle;
  if (smooth > 0.0f && t < smooth) {
    const float x = t / smooth;
    return inside * x * x * (3.0f - 2.0f * x);
  }
  return inside;
}

float Light::area() const {
  const float a = area_width * area_height;
  return area_shape == AreaShape::Ellipse ? a * 0.25f * std::numbers::pi_v<float> : a;
}

void Light::illuminate(const V3f& p_world, V3f& to_light, V3f& irradiance, float u1,
                       float u2) const {
  V3f emitter = position_world;
  if (type == LightType::Area) {
    // A uniform point of the shape: the average of I0 cos / d^2 over the
    // shape is the irradiance of a Lambertian emitter of radiance I0 / area.
    float x, y;
    if (area_shape == AreaShape::Ellipse) {
      concentric_disk(u1, u2, x, y);
      x *= 0.5f;
      y *= 0.5f;
    } else {
      x = u1 - 0.5f;
      y = u2 - 0.5f;
    }
    emitter += side_world * (x * area_width) + axis_world.cross(side_world) * (y * area_height);
  }
  const V3f offset = type == LightType::Directional ? to_light_world : emitter - p_world;
  const float dist2 = offset.length2();
  if (!(dist2 > 0.0f) || !std::isfinite(dist2)) {
    to_light = V3f(0, 0, 1);
    irradiance = V3f(0, 0, 0);
    return;
  }
  const float dist = std::sqrt(dist2);
  to_light = offset / dist;
  switch (type) {
    case LightType::Directional:  // constant irradiance
      irradiance = color * intensity;
      return;
    case LightType::Point:  // inverse square law
      irradiance = color * (intensity / dist2);
      return;
    case LightType::Spot:
      irradiance = color * (intensity *
                            spot_attenuation(-to_light.dot(axis_world), spot_cos_half_angle,
                                             spot_smooth, spot_axis_cosine) /
                            dist2);
      return;
    case LightType::Area: {
      // One-sided: nothing leaves the back of the shape.
      const float cos_light = std::max(-to_light.dot(axis_world), 0.0f);
      irradiance = color * (intensity * cos_light / dist2);
      return;
    }
  }
}

}  // namespace clothbake
