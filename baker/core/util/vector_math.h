#pragma once
/// Small numeric helpers: vectors for the fibre model's forms (and anything
/// that must never turn a degenerate input into NaN), and the wrap of a
/// periodic grid's coordinate.

#include <algorithm>
#include <cmath>

#include <Imath/ImathVec.h>

namespace clothbake {

inline bool finite(const Imath::V3f& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// Normalises `a`; returns false (and leaves `a` alone) for a zero vector. The
/// vector is pre-scaled by its largest component so tiny and huge inputs work.
inline bool normalize_safe(Imath::V3f& a) {
  const float len2 = a.dot(a);
  if (len2 > 1.0e-30f && len2 < 1.0e30f) {  // the usual case: no over/underflow
    a *= 1.0f / std::sqrt(len2);
    return true;
  }
  const float m = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)});
  if (!(m > 0.0f)) return false;
  const Imath::V3f s = a * (1.0f / m);
  a = s * (1.0f / std::sqrt(s.dot(s)));
  return true;
}

/// floor(g) wrapped into [0, n) and the fraction, for a coordinate g of a
/// periodic grid of n points (the material's texels, the light fields, the
/// transmittance caches) that may lie many repeats away. `inv_n` = 1 / n, so
/// that the wrap costs a multiplication, not a division.
inline void wrap_floor(float g, int n, float inv_n, int& i, float& frac) {
  const float gw = g - std::floor(g * inv_n) * float(n);
  i = std::min(int(gw), n - 1);
  frac = gw - float(i);
}

}  // namespace clothbake
