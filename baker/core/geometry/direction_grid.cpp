#include "core/geometry/direction_grid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clothbake {

using Imath::V2f;
using Imath::V3f;

V2f hemi_oct_encode(const V3f& d) {
  const float norm = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  if (!(norm > 0.0f)) return V2f(0.5f, 0.5f);
  const float px = d.x / norm, py = d.y / norm;
  return V2f(std::clamp((px + py + 1.0f) * 0.5f, 0.0f, 1.0f),
             std::clamp((px - py + 1.0f) * 0.5f, 0.0f, 1.0f));
}

V3f hemi_oct_decode(const V2f& uv) {
  const float a = 2.0f * uv.x - 1.0f, b = 2.0f * uv.y - 1.0f;
  const float px = 0.5f * (a + b), py = 0.5f * (a - b);
  const float z = std::max(0.0f, 1.0f - std::fabs(px) - std::fabs(py));
  return V3f(px, py, z).normalized();
}

namespace {
/// The horizon warp of DirectionMap::HemiOctahedralHorizon on the diamond.
V2f warp_toward_horizon(V2f p, bool to_grid) {
  const float rho = std::fabs(p.x) + std::fabs(p.y);
  if (!(rho > 0.0f)) return p;
  const float r = std::min(rho, 1.0f);
  const float mapped = to_grid ? 1.0f - std::sqrt(1.0f - r) : 1.0f - (1.0f - r) * (1.0f - r);
  return p * (mapped / rho);
}
}  // namespace

V3f DirectionGrid::node_direction(int side, int i, int j) const {
  V3f d;
  if (map == DirectionMap::HemiOctahedralHorizon) {
    const float a = 2.0f * float(i) / float(k - 1) - 1.0f, b = 2.0f * float(j) / float(k - 1) - 1.0f;
    const V2f p = warp_toward_horizon(V2f(0.5f * (a + b), 0.5f * (a - b)), false);
    d = V3f(p.x, p.y, std::max(0.0f, 1.0f - std::fabs(p.x) - std::fabs(p.y))).normalized();
  } else if (map == DirectionMap::Polar) {
    const float phi = 2.0f * std::numbers::pi_v<float> * float(i) / float(k);
    const float theta = 0.5f * std::numbers::pi_v<float> * float(j) / float(k - 1);
    d = V3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  } else {
    d = hemi_oct_decode(V2f(float(i) / float(k - 1), float(j) / float(k - 1)));
  }
  if (side == 1) d.z = -d.z;
  return d;
}

V3f DirectionGrid::bake_direction(int side, int i, int j) const {
  const V3f d = node_direction(side, i, j);
  const float min_z = 0.0174524f;  // sin(1 degree)
  if (std::fabs(d.z) >= min_z) return d;
  const float xy = std::sqrt(std::max(0.0f, 1.0f - min_z * min_z));
  const float len = std::hypot(d.x, d.y);
  // The node's side, not the sign of its z: horizon nodes have z = -0 (back,
  // hemi-octahedral) or -+4e-8 (polar, cos(float(pi/2)) < 0), which baked
  // the back horizon from the front (and polar's front from the back); the
  // lookup then showed the lit side at grazing back views, 14 x too bright
  // (tests/core/stability_test.cpp, LookupCoarseKAtGrazingViews).
  const float sign = side == 1 ? -1.0f : 1.0f;
  return len > 0.0f ? V3f(d.x / len * xy, d.y / len * xy, sign * min_z) : V3f(0, 0, sign);
}

DirectionGrid::Footprint DirectionGrid::locate(const V3f& to_eye_in) const {
  // A NaN or infinite direction has no place on either map; it used to give
  // grid indices of INT_MIN (int(NaN)), read out of bounds by
  // LookupTable::sample (tests/core/stability_test.cpp). Read it as the
  // normal, as hemi_oct_encode already did for NaN.
  const bool finite_dir =
      std::isfinite(to_eye_in.x) && std::isfinite(to_eye_in.y) && std::isfinite(to_eye_in.z);
  const V3f to_eye_local = finite_dir ? to_eye_in : V3f(0.0f, 0.0f, 1.0f);
  Footprint f;
  f.side = to_eye_local.z >= 0.0f ? 0 : 1;
  if (map == DirectionMap::Polar) {
    constexpr float pi = std::numbers::pi_v<float>;
    const float len = to_eye_local.length();
    const float z = len > 0.0f ? std::fabs(to_eye_local.z) / len : 1.0f;
    const float theta = std::acos(std::clamp(z, 0.0f, 1.0f));
    float phi = std::atan2(to_eye_local.y, to_eye_local.x);
    if (phi < 0.0f) phi += 2.0f * pi;
    const float gx = phi / (2.0f * pi) * float(k);
    const float gy = std::clamp(theta / (0.5f * pi) * float(k - 1), 0.0f, float(k - 1));
    f.i0 = std::min(int(gx), k - 1);
    f.i1 = f.i0 + 1 == k ? 0 : f.i0 + 1;  // azimuth wraps around
    f.fx = std::clamp(gx - float(f.i0), 0.0f, 1.0f);
    f.j0 = std::min(int(gy), k - 2);
    f.j1 = f.j0 + 1;
    f.fy = std::clamp(gy - float(f.j0), 0.0f, 1.0f);
    return f;
  }
  V2f uv = hemi_oct_encode(to_eye_local);
  if (map == DirectionMap::HemiOctahedralHorizon) {
    const float a = 2.0f * uv.x - 1.0f, b = 2.0f * uv.y - 1.0f;
    const V2f p = warp_toward_horizon(V2f(0.5f * (a + b), 0.5f * (a - b)), true);
    uv = V2f(std::clamp((p.x + p.y + 1.0f) * 0.5f, 0.0f, 1.0f),
             std::clamp((p.x - p.y + 1.0f) * 0.5f, 0.0f, 1.0f));
  }
  const float gx = uv.x * float(k - 1), gy = uv.y * float(k - 1);
  f.i0 = std::min(int(gx), k - 2);
  f.j0 = std::min(int(gy), k - 2);
  f.i1 = f.i0 + 1;
  f.j1 = f.j0 + 1;
  f.fx = std::clamp(gx - float(f.i0), 0.0f, 1.0f);
  f.fy = std::clamp(gy - float(f.j0), 0.0f, 1.0f);
  return f;
}

}  // namespace clothbake
