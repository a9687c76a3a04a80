#include "core/material/view_parallax.h"

#include <algorithm>
#include <cmath>

namespace clothbake {

using Imath::V2f;
using Imath::V3f;

V2f material_slope(const V3f& d) {
  const float z = std::max(std::fabs(d.z), k_parallax_min_z);
  return V2f(d.x / z, d.y / z);
}

V2f parallax_shift_mm(const V3f& to_eye, const V3f& node, float depth_mm, float depth_scale) {
  if (depth_mm == 0.0f) return V2f(0.0f);
  // Both rays run into the cloth along -direction: at depth h the eye's is
  // at x - h slope(eye), the node's entering at x' at x' - h slope(node).
  return (material_slope(to_eye) - material_slope(node)) * (-depth_mm / depth_scale);
}

}  // namespace clothbake
