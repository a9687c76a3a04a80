#include "core/material/light_fields.h"

#include <algorithm>
#include <cmath>

#include "core/march/light_transmittance.h"
#include "core/util/vector_math.h"

namespace clothbake {

namespace {
using Imath::V3f;

/// The same medium on a grid `s` times finer: each cell's density copied
/// into its s^3 sub-cells (the only field the transmittance reads).
VolumeTexture refine(const VolumeTexture& volume, int s) {
  if (s == 1) return volume;
  VolumeTexture fine(volume.nx() * s, volume.ny() * s, volume.nz() * s, volume.size_mm());
  for (int k = 0; k < fine.nz(); ++k)
    for (int j = 0; j < fine.ny(); ++j)
      for (int i = 0; i < fine.nx(); ++i)
        fine.at(i, j, k).density = volume.at_wrapped(i / s, j / s, k / s).density;
  return fine;
}

}  // namespace

size_t LightFieldSet::bytes_for(const VolumeTexture& volume, int lights, int s) {
  return size_t(volume.nx()) * s * size_t(volume.ny()) * s * (size_t(volume.nz()) * s + 2) *
         size_t(lights) * sizeof(float);
}

LightFieldSet LightFieldSet::build(const VolumeTexture& volume, std::span<const V3f> to_light,
                                   float sigma, int supersample) {
  const VolumeTexture fine = refine(volume, std::max(1, supersample));
  LightFieldSet set;
  set.m_nx = fine.nx();
  set.m_ny = fine.ny();
  set.m_nz = fine.nz();
  set.m_lights = int(to_light.size());
  set.m_spacing = fine.cell_size_mm();
  set.m_thickness = fine.size_mm().z;
  const size_t L = to_light.size();
  const size_t layer = size_t(set.m_nx) * set.m_ny;
  set.m_tau.assign(layer * size_t(set.m_nz + 2) * L, 0.0f);
  for (size_t l = 0; l < L; ++l) {
    const TransmittanceCache cache = TransmittanceCache::build(fine, to_light[l], sigma);
    const bool from_above = to_light[l].z >= 0.0f;
    for (int kz = 0; kz < set.m_nz + 2; ++kz) {
      // kz = 0 and nz + 1 are the faces: 0 on the face the light enters by,
      // the outermost layer's value held on the other.
      int k = std::clamp(kz - 1, 0, set.m_nz - 1);
      const bool entry_face = from_above ? kz == set.m_nz + 1 : kz == 0;
      for (int j = 0; j < set.m_ny; ++j)
        for (int i = 0; i < set.m_nx; ++i)
          set.m_tau[((size_t(kz) * set.m_ny + j) * set.m_nx + i) * L + l] =
              entry_face ? 0.0f : cache.depth_at(i, j, k);
    }
  }
  return set;
}

size_t LightFieldSet::bytes_for_window(const VolumeTexture& volume, int cells_x, int cells_y,
                                       int lights, int s) {
  return size_t(std::min(cells_x, volume.nx())) * s * size_t(std::min(cells_y, volume.ny())) * s *
         (size_t(volume.nz()) * s + 2) * size_t(lights) * sizeof(float);
}

LightFieldSet LightFieldSet::build_window(const VolumeTexture& volume, int x0, int y0, int cells_x,
                                          int cells_y, std::span<const V3f> to_light, float sigma,
                                          int supersample) {
  if (cells_x >= volume.nx() && cells_y >= volume.ny())
    return build(volume, to_light, sigma, supersample);
  // An axis the window spans whole stays the volume's own, from cell 0.
  if (cells_x >= volume.nx()) x0 = 0, cells_x = volume.nx();
  if (cells_y >= volume.ny()) y0 = 0, cells_y = volume.ny();
  const V3f cell = volume.cell_size_mm();
  VolumeTexture window(cells_x, cells_y, volume.nz(),
                       V3f(float(cells_x) * cell.x, float(cells_y) * cell.y, volume.size_mm().z));
  for (int k = 0; k < volume.nz(); ++k)
    for (int j = 0; j < cells_y; ++j)
      for (int i = 0; i < cells_x; ++i) window.at(i, j, k) = volume.at(x0 + i, y0 + j, k);
  LightFieldSet set = build(window, to_light, sigma, supersample);
  set.m_origin = Imath::V2f(float(x0) * cell.x, float(y0) * cell.y);
  set.m_window = Imath::V2f(window.size_mm().x, window.size_mm().y);
  set.m_repeat = Imath::V2f(volume.size_mm().x, volume.size_mm().y);
  return set;
}

void LightFieldSet::depths(const V3f& p_volume, float* depth) const {
  V3f p = p_volume;
  if (m_repeat.x > 0.0f) {
    // Into the window's frame, from the repeat's copy nearest its centre.
    for (int a = 0; a < 2; ++a) {
      float d = p[a] - m_origin[a];
      d -= m_repeat[a] * std::round((d - 0.5f * m_window[a]) / m_repeat[a]);
      p[a] = d;
    }
  }
  int xa, ya;
  float fx, fy;
  wrap_floor(p.x / m_spacing.x - 0.5f, m_nx, 1.0f / float(m_nx), xa, fx);
  wrap_floor(p.y / m_spacing.y - 0.5f, m_ny, 1.0f / float(m_ny), ya, fy);
  const int xb = xa + 1 == m_nx ? 0 : xa + 1, yb = ya + 1 == m_ny ? 0 : ya + 1;
  // z: the faces (kz = 0 at z = 0, kz = nz + 1 at the top) and the layer
  // centres between them (kz = k + 1 at (k + 0.5) dz).
  const float gz = p.z / m_spacing.z - 0.5f;  // in layer-centre units
  int z0, z1;
  float fz;
  if (gz < 0.0f) {
    z0 = 0, z1 = 1;
    fz = std::clamp(1.0f + 2.0f * gz, 0.0f, 1.0f);  // face at gz = -0.5
  } else if (gz >= float(m_nz - 1)) {
    z0 = m_nz, z1 = m_nz + 1;
    fz = std::clamp(2.0f * (gz - float(m_nz - 1)), 0.0f, 1.0f);  // face at nz - 0.5
  } else {
    const int k = std::min(int(gz), m_nz - 2);
    z0 = k + 1, z1 = k + 2;
    fz = gz - float(k);
  }
  const size_t L = size_t(m_lights);
  const auto corner = [&](int i, int j, int kz) {
    return m_tau.data() + ((size_t(kz) * m_ny + j) * m_nx + i) * L;
  };
  const float* c[8] = {corner(xa, ya, z0), corner(xb, ya, z0), corner(xa, yb, z0),
                       corner(xb, yb, z0), corner(xa, ya, z1), corner(xb, ya, z1),
                       corner(xa, yb, z1), corner(xb, yb, z1)};
  const float w[8] = {(1 - fx) * (1 - fy) * (1 - fz), fx * (1 - fy) * (1 - fz),
                      (1 - fx) * fy * (1 - fz),       fx * fy * (1 - fz),
                      (1 - fx) * (1 - fy) * fz,       fx * (1 - fy) * fz,
                      (1 - fx) * fy * fz,             fx * fy * fz};
  for (size_t l = 0; l < L; ++l) depth[l] = 0.0f;
  for (int n = 0; n < 8; ++n) {
    if (w[n] == 0.0f) continue;
    const float* src = c[n];
    const float wn = w[n];
    for (size_t l = 0; l < L; ++l) depth[l] += wn * src[l];
  }
}

void LightFieldSet::transmittances(const V3f& p, float* t) const {
  depths(p, t);
  for (int l = 0; l < m_lights; ++l) t[l] = TransmittanceCache::transmittance(t[l]);
}

}  // namespace clothbake
