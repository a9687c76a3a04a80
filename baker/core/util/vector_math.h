#pragma once
/// Small vector helpers shared by the fibre model's forms (and anything that
/// must never turn a degenerate input into NaN).

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

}  // namespace clothbake
