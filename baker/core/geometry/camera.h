#pragma once
/// Pinhole camera. Pixel (0, 0) is the top-left corner of the image; pixel
/// centres are at half-integers. The field of view is the full angle across
/// the image along `fov_axis`. The scene reader rejects degenerate cameras;
/// should one reach here anyway, nothing becomes NaN: look_at == position looks
/// down -z, an up vector that is zero or parallel to the view is replaced by
/// the world axis least aligned with it, fov is clamped into (0, 180).

#include <Imath/ImathVec.h>

namespace clothbake {

struct Ray {
  Imath::V3f origin_world;
  Imath::V3f direction_world;  ///< unit
};

enum class FovAxis { Horizontal, Vertical };

struct PinholeCamera {
  Imath::V3f position_world{0, 0, 5};
  Imath::V3f look_at_world{0, 0, 0};
  Imath::V3f up_world{0, 1, 0};
  float fov_deg = 40.0f;  ///< full angle, (0, 180)
  FovAxis fov_axis = FovAxis::Horizontal;
  int width = 426;   ///< pixels
  int height = 266;  ///< pixels

  /// Ray through the continuous image position (x, y) in pixels.
  Ray generate_ray(float x, float y) const;
  /// Image position (pixels) of a world point; false if behind the camera.
  bool project(const Imath::V3f& p_world, float& x, float& y) const;
};

}  // namespace clothbake
