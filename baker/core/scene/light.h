#pragma once
/// Lights of a scene: directional (sun-like), point, spot (a point light
/// masked by Blender's cone) and area (a one-sided emitting rectangle or
/// ellipse, sampled).

#include <Imath/ImathVec.h>

namespace clothbake {

enum class LightType { Directional, Point, Spot, Area };

/// The shape of an area light, in its own plane (Blender's square and disk
/// are a rectangle and an ellipse with equal sides).
enum class AreaShape { Rectangle, Ellipse };

struct Light {
  LightType type = LightType::Directional;
  Imath::V3f to_light_world{0, 0, 1};  ///< directional: unit vector toward the light
  Imath::V3f position_world{0, 0, 0};  ///< point, spot: position; area: centre
  Imath::V3f color{1, 1, 1};           ///< linear RGB
  /// Directional: irradiance on a surface facing it. Point and spot:
  /// intensity (irradiance at 1 world unit; a spot's on its axis, before the
  /// cone). Area: radiant intensity along its normal (radiance x area), so
  /// that far away it lights as a point light of that intensity times the
  /// cosine off its normal.
  float intensity = 1.0f;

  /// Spot and area: the unit direction the light travels along (the cone's
  /// axis; the area light's emitting normal). Area: the unit axis of its
  /// first side, orthogonal to `axis_world`; the second is axis x side.
  Imath::V3f axis_world{0, 0, -1};
  Imath::V3f side_world{1, 0, 0};
  /// Spot: cos(half the cone angle) and the width of Cycles' smoothstep on
  /// the cosine, (1 - cos_half_angle) x blend.
  float spot_cos_half_angle = 0.0f;
  float spot_smooth = 0.0f;
  /// Spot: whether the mask holds one more cosine of the angle off the axis,
  /// as Blender 3.x's spot does; Blender 4.0 and later have the smoothstep
  /// alone (docs/formats/scene.md, "axis_cosine").
  bool spot_axis_cosine = true;
  /// Area: shape and the two side lengths (world units; an ellipse's axes).
  AreaShape area_shape = AreaShape::Rectangle;
  float area_width = 1.0f, area_height = 1.0f;

  /// Whether the light is sampled (an area light): illuminate() then takes
  /// a point of [0,1)^2 and the average over uniform points is the light's
  /// irradiance. Other lights ignore the point.
  bool sampled() const { return type == LightType::Area; }

  /// Unit direction toward the light from p_world and the irradiance arriving
  /// there (before any transmittance through the cloth) on a surface facing
  /// it. `u1, u2` in [0,1) pick the point of an area light. A point light at
  /// zero distance, a zero direction, a point outside a spot's cone or
  /// behind an area light gives zero irradiance (never NaN).
  void illuminate(const Imath::V3f& p_world, Imath::V3f& to_light, Imath::V3f& irradiance,
                  float u1 = 0.5f, float u2 = 0.5f) const;

  /// The area of an area light's shape (world units squared).
  float area() const;
};

/// Cycles' spot mask for the cosine between the cone's axis and the
/// direction from the light to the point: zero outside the cone, rolled off
/// by a smoothstep over `smooth` at the edge, and 1 inside, or the cosine
/// itself with `axis_cosine` (Blender 3.x's mask).
float spot_attenuation(float cos_axis, float cos_half_angle, float smooth, bool axis_cosine);

}  // namespace clothbake
