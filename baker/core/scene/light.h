#pragma once
/// Lights of a scene: directional (sun-like) and point.

#include <Imath/ImathVec.h>

namespace clothbake {

enum class LightType { Directional, Point };

struct Light {
  LightType type = LightType::Directional;
  Imath::V3f to_light_world{0, 0, 1};  ///< directional: unit vector toward the light
  Imath::V3f position_world{0, 0, 0};  ///< point: position
  Imath::V3f color{1, 1, 1};           ///< linear RGB
  float intensity = 1.0f;  ///< directional: irradiance on a surface facing it; point: intensity
                           ///< (irradiance at 1 world unit)

  /// Unit direction toward the light from p_world and the irradiance arriving
  /// there (before any transmittance through the cloth). A point light at
  /// zero distance, or a zero direction, gives zero irradiance (never NaN).
  void illuminate(const Imath::V3f& p_world, Imath::V3f& to_light, Imath::V3f& irradiance) const;
};

}  // namespace clothbake
