#pragma once
/// 3-D DDA through the periodic cell grid of a volume texture (Amanatides &
/// Woo 1987): lists the cells a texture-space ray crosses, in order, with the
/// ray segment inside each (PAPER.md s.5 steps 2 and 3a). x and y wrap, z is
/// bounded by the volume's bottom and top faces.

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/texture/volume_texture.h"

namespace clothbake {

/// Calls visit(cell, t0, t1) for each cell crossed by p + t d, t in [0, t_max]
/// (d unit, texture mm), until visit returns false, t_max is reached or the
/// ray leaves through the bottom or top face. Returns the t where it stopped.
template <typename Visit>
float walk_cells(const VolumeTexture& volume, const Imath::V3f& p_texture,
                 const Imath::V3f& d_texture, float t_max, Visit&& visit) {
  const Imath::V3f cell = volume.cell_size_mm();
  const float inf = std::numeric_limits<float>::infinity();
  int idx[3], step[3];
  float t_next[3], t_delta[3];
  for (int a = 0; a < 3; ++a) {
    const float c = cell[a];
    idx[a] = int(std::floor(p_texture[a] / c));
    // A point on (or a rounding error beyond) the top or bottom face belongs
    // to the outermost layer.
    if (a == 2) idx[a] = std::clamp(idx[a], 0, volume.nz() - 1);
    if (d_texture[a] > 0.0f) {
      step[a] = 1;
      t_delta[a] = c / d_texture[a];
      t_next[a] = (float(idx[a] + 1) * c - p_texture[a]) / d_texture[a];
    } else if (d_texture[a] < 0.0f) {
      step[a] = -1;
      t_delta[a] = -c / d_texture[a];
      t_next[a] = (float(idx[a]) * c - p_texture[a]) / d_texture[a];
    } else {
      step[a] = 0;
      t_delta[a] = inf;
      t_next[a] = inf;
    }
  }
  // Track x and y inside the repeat so each step wraps by a compare, not a
  // division.
  const int n[2] = {volume.nx(), volume.ny()};
  for (int a = 0; a < 2; ++a) idx[a] = ((idx[a] % n[a]) + n[a]) % n[a];
  float t = 0.0f;
  while (t < t_max) {
    const int a =
        t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const float t_exit = std::min(t_next[a], t_max);
    if (t_exit > t && !visit(volume.at_wrapped(idx[0], idx[1], idx[2]), t, t_exit)) return t_exit;
    t = t_exit;
    if (t >= t_max) break;
    idx[a] += step[a];
    t_next[a] += t_delta[a];
    if (a == 2) {
      if (idx[2] < 0 || idx[2] >= volume.nz()) break;
    } else if (idx[a] == n[a]) {
      idx[a] = 0;
    } else if (idx[a] < 0) {
      idx[a] = n[a] - 1;
    }
  }
  return t;
}

/// The longest texture path one march takes, view or shadow: 64 repeats
/// of the texture. A ray near the horizon would otherwise cross the periodic
/// texture without end.
inline float march_cap_mm(const VolumeTexture& volume) {
  return 64.0f * std::max(volume.size_mm().x, volume.size_mm().y);
}

/// Distance along d (unit, texture mm) from p to the face the ray leaves by:
/// the top face if d.z > 0, the bottom if d.z < 0, `cap` if parallel.
inline float distance_to_exit(const VolumeTexture& volume, const Imath::V3f& p_texture,
                              const Imath::V3f& d_texture, float cap) {
  if (d_texture.z > 0.0f)
    return std::min(cap, std::max(0.0f, (volume.size_mm().z - p_texture.z) / d_texture.z));
  if (d_texture.z < 0.0f) return std::min(cap, std::max(0.0f, -p_texture.z / d_texture.z));
  return cap;
}

}  // namespace clothbake
