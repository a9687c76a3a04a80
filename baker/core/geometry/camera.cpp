// Pinhole camera: pixel positions to world rays and back.
//
// Degenerate set-ups are the scene reader's to reject; here they never turn
// into NaN: look_at == position looks down -z, an up vector parallel to the
// view direction (or zero) is replaced by the world axis least aligned with
// it, and fov_deg is clamped into (0, 180).

#include "core/geometry/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clothbake {
namespace {

using Imath::V3d;

V3d to_d(const Imath::V3f& v) { return V3d(v.x, v.y, v.z); }

/// The camera's orthonormal basis and focal length in pixels.
struct CameraBasis {
  V3d forward, right, up;
  double focal_px = 1.0;
};

CameraBasis basis_of(const PinholeCamera& cam) {
  CameraBasis basis;
  basis.forward = to_d(cam.look_at_world) - to_d(cam.position_world);
  const double forward_len = basis.forward.length();
  basis.forward =
      forward_len > 0.0 && std::isfinite(forward_len) ? basis.forward / forward_len : V3d(0, 0, -1);
  // right = forward x up; fall back to the world axis least aligned with forward.
  V3d right = basis.forward.cross(to_d(cam.up_world));
  if (!(right.length() > 1e-6 * to_d(cam.up_world).length())) {
    const V3d f = basis.forward;
    const V3d axis = std::abs(f.x) <= std::abs(f.y) && std::abs(f.x) <= std::abs(f.z) ? V3d(1, 0, 0)
                     : std::abs(f.y) <= std::abs(f.z)                                 ? V3d(0, 1, 0)
                                                      : V3d(0, 0, 1);
    right = f.cross(axis);
  }
  basis.right = right.normalized();
  basis.up = basis.right.cross(basis.forward);

  const double fov_rad =
      std::clamp(double(cam.fov_deg), 1e-3, 180.0 - 1e-3) * (std::numbers::pi / 180.0);
  const double extent_px = cam.fov_axis == FovAxis::Horizontal ? cam.width : cam.height;
  basis.focal_px = 0.5 * std::max(extent_px, 1.0) / std::tan(0.5 * fov_rad);
  return basis;
}

}  // namespace

Ray PinholeCamera::generate_ray(float x, float y) const {
  const CameraBasis basis = basis_of(*this);
  // Image y grows downward, so it runs against the camera's up vector.
  const V3d dir = basis.forward * basis.focal_px + basis.right * (double(x) - 0.5 * width) -
                  basis.up * (double(y) - 0.5 * height);
  const V3d unit = dir.normalized();
  return Ray{position_world, Imath::V3f(float(unit.x), float(unit.y), float(unit.z))};
}

bool PinholeCamera::project(const Imath::V3f& p_world, float& x, float& y) const {
  const CameraBasis basis = basis_of(*this);
  const V3d d = to_d(p_world) - to_d(position_world);
  const double depth = d.dot(basis.forward);
  if (!(depth > 0.0)) return false;  // at or behind the camera plane
  const double px = 0.5 * width + basis.focal_px * d.dot(basis.right) / depth;
  const double py = 0.5 * height - basis.focal_px * d.dot(basis.up) / depth;
  if (!std::isfinite(float(px)) || !std::isfinite(float(py))) return false;
  x = float(px);
  y = float(py);
  return true;
}

}  // namespace clothbake
