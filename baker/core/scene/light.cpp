// Lights: the direction toward a light and the irradiance it delivers.
//
// Degenerate lights never produce NaN: a zero (or non-finite) directional
// vector, or a surface point at a point light's position, gives zero
// irradiance and the placeholder direction +z.

#include "core/scene/light.h"

#include <cmath>

namespace clothbake {

void Light::illuminate(const Imath::V3f& p_world, Imath::V3f& to_light,
                       Imath::V3f& irradiance) const {
  const Imath::V3f offset =
      type == LightType::Directional ? to_light_world : position_world - p_world;
  const float dist2 = offset.length2();
  if (!(dist2 > 0.0f) || !std::isfinite(dist2)) {
    to_light = Imath::V3f(0, 0, 1);
    irradiance = Imath::V3f(0, 0, 0);
    return;
  }
  const float dist = std::sqrt(dist2);
  to_light = offset / dist;
  // Directional: constant irradiance; point: inverse square law.
  irradiance = type == LightType::Directional ? color * intensity : color * (intensity / dist2);
}

}  // namespace clothbake
