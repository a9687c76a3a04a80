#include "core/march/light_transmittance.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/march/cell_walk.h"
#include "core/util/vector_math.h"

namespace clothbake {

namespace {
using Imath::V3f;

/// sigma * integral of rho along p + t d, t in [0, length], stopping early
/// once the light is blocked.
float optical_depth(const VolumeTexture& volume, const V3f& p, const V3f& d, float length,
                    float sigma) {
  float tau = 0.0f;
  walk_cells(volume, p, d, length, [&](const Cell& c, float t0, float t1) {
    tau += sigma * c.density * (t1 - t0);
    return tau < k_opaque_optical_depth;
  });
  return tau;
}

}  // namespace

float shadow_transmittance(const VolumeTexture& volume, const V3f& p_texture,
                           const V3f& to_light_texture, float extinction_per_mm) {
  const float length = distance_to_exit(volume, p_texture, to_light_texture, march_cap_mm(volume));
  const float tau = optical_depth(volume, p_texture, to_light_texture, length, extinction_per_mm);
  return tau >= k_opaque_optical_depth ? 0.0f : std::exp(-tau);
}

// About 85 lines, kept whole: one sweep over the cells in light order, whose
// running sums the steps share.
TransmittanceCache TransmittanceCache::build(const VolumeTexture& volume, const V3f& to_light,
                                             float sigma) {
  TransmittanceCache cache;
  cache.m_nx = volume.nx();
  cache.m_ny = volume.ny();
  cache.m_nz = volume.nz();
  cache.m_cell = volume.cell_size_mm();
  cache.m_tau.assign(volume.cell_count(), 0.0f);
  cache.m_from_above = to_light.z >= 0.0f;
  cache.m_to_light = to_light;
  const V3f cell = cache.m_cell;
  const int nx = cache.m_nx, ny = cache.m_ny, nz = cache.m_nz;
  auto at = [&](int i, int j, int k) -> float& {
    return cache.m_tau[(size_t(k) * ny + j) * nx + i];
  };
  // Nearly horizontal light: layer-by-layer propagation would interpolate
  // over very long segments; march every cell exactly instead.
  const bool grazing = std::fabs(to_light.z) < 0.02f;
  if (grazing) {
    tbb::parallel_for(0, nz * ny, [&](int row) {
      const int k = row / ny, j = row % ny;
      for (int i = 0; i < nx; ++i) {
        const V3f p((i + 0.5f) * cell.x, (j + 0.5f) * cell.y, (k + 0.5f) * cell.z);
        at(i, j, k) =
            optical_depth(volume, p, to_light,
                          distance_to_exit(volume, p, to_light, march_cap_mm(volume)), sigma);
      }
    });
    return cache;
  }
  // The layer nearest the light: exact march to the face. Then each further
  // layer: exact segment to the previous layer's centre plane, times the
  // transmittance there (bilinear between that layer's cell centres).
  const bool from_above = to_light.z > 0.0f;
  const int first = from_above ? nz - 1 : 0, dir = from_above ? -1 : 1;
  const float seg = cell.z / std::fabs(to_light.z);  // length between centre planes
  const V3f shift = to_light * seg;                  // offset to the previous plane
  // Two sub-segments per layer crossed (one in each half-layer), more when
  // the segment runs across several cells sideways.
  const float across_cells = std::max(std::fabs(shift.x) / cell.x, std::fabs(shift.y) / cell.y);
  const int n_sub = std::max(2, int(std::ceil(2.0f * across_cells)));
  const float inv_nx = 1.0f / float(nx), inv_ny = 1.0f / float(ny);
  for (int n = 0; n < nz; ++n) {
    const int k = first + dir * n;
    tbb::parallel_for(0, ny, [&](int j) {
      for (int i = 0; i < nx; ++i) {
        const V3f p((i + 0.5f) * cell.x, (j + 0.5f) * cell.y, (k + 0.5f) * cell.z);
        if (n == 0) {
          at(i, j, k) =
              optical_depth(volume, p, to_light,
                            distance_to_exit(volume, p, to_light, march_cap_mm(volume)), sigma);
          continue;
        }
        // Bilinear in the previous layer, periodic.
        int xa, ya;
        float fx, fy;
        wrap_floor((p.x + shift.x) / cell.x - 0.5f, nx, inv_nx, xa, fx);
        wrap_floor((p.y + shift.y) / cell.y - 0.5f, ny, inv_ny, ya, fy);
        const int xb = xa + 1 == nx ? 0 : xa + 1, yb = ya + 1 == ny ? 0 : ya + 1;
        const int kp = k - dir;
        const float prev = (at(xa, ya, kp) * (1 - fx) + at(xb, ya, kp) * fx) * (1 - fy) +
                           (at(xa, yb, kp) * (1 - fx) + at(xb, yb, kp) * fx) * fy;
        if (prev >= k_opaque_optical_depth) {  // already dark: the segment cannot matter
          at(i, j, k) = k_opaque_optical_depth;
          continue;
        }
        // The segment to the previous layer's centre plane, by the midpoint
        // rule over sub-segments no longer than half a cell across.
        float rho_sum = 0.0f;
        for (int m = 0; m < n_sub; ++m) {
          const V3f q = p + to_light * (seg * (m + 0.5f) / n_sub);
          int qi, qj;
          float unused;
          wrap_floor(q.x / cell.x, nx, inv_nx, qi, unused);
          wrap_floor(q.y / cell.y, ny, inv_ny, qj, unused);
          const int qk = std::clamp(int(std::floor(q.z / cell.z)), 0, nz - 1);
          rho_sum += volume.at_wrapped(qi, qj, qk).density;
        }
        const float tau = sigma * seg * rho_sum / n_sub;
        at(i, j, k) = std::min(k_opaque_optical_depth, tau + prev);
      }
    });
  }
  return cache;
}

float TransmittanceCache::lookup_depth(const V3f& p) const {
  float gz = p.z / m_cell.z - 0.5f;
  int xa, ya;
  float fx, fy;
  wrap_floor(p.x / m_cell.x - 0.5f, m_nx, 1.0f / float(m_nx), xa, fx);
  wrap_floor(p.y / m_cell.y - 0.5f, m_ny, 1.0f / float(m_ny), ya, fy);
  const int xb = xa + 1 == m_nx ? 0 : xa + 1, yb = ya + 1 == m_ny ? 0 : ya + 1;
  auto tau = [&](int i, int j, int k) { return m_tau[(size_t(k) * m_ny + j) * m_nx + i]; };
  auto layer = [&](int k) {
    return (tau(xa, ya, k) * (1 - fx) + tau(xb, ya, k) * fx) * (1 - fy) +
           (tau(xa, yb, k) * (1 - fx) + tau(xb, yb, k) * fx) * fy;
  };
  float depth;
  // Between the face the light enters by (optical depth 0 everywhere on it)
  // and the outermost layer's centres: interpolate toward 0.
  if (m_from_above && gz > float(m_nz - 1)) {
    const float f = std::min(1.0f, (gz - float(m_nz - 1)) * 2.0f);
    depth = layer(m_nz - 1) * (1.0f - f);
  } else if (!m_from_above && gz < 0.0f) {
    const float f = std::min(1.0f, -gz * 2.0f);
    depth = layer(0) * (1.0f - f);
  } else {
    gz = std::clamp(gz, 0.0f, float(m_nz - 1));
    const int z0 = std::min(int(gz), std::max(m_nz - 2, 0));
    const int z1 = std::min(z0 + 1, m_nz - 1);
    const float fz = z1 > z0 ? gz - float(z0) : 0.0f;
    depth = layer(z0) * (1.0f - fz) + layer(z1) * fz;
  }
  return depth;
}

float TransmittanceCache::march_then_lookup(const VolumeTexture& volume, const V3f& p,
                                            const V3f& to_light, float sigma) const {
  const float gz = p.z / m_cell.z - 0.5f;
  // The first layer-centre plane beyond p toward the light.
  const int k = m_from_above ? int(std::floor(gz)) + 1 : int(std::ceil(gz)) - 1;
  if (k < 0 || k >= m_nz || std::fabs(to_light.z) < 1e-4f) {
    const float length = distance_to_exit(volume, p, to_light, march_cap_mm(volume));
    return optical_depth(volume, p, to_light, length, sigma);
  }
  const float length = ((k + 0.5f) * m_cell.z - p.z) / to_light.z;
  const float near = optical_depth(volume, p, to_light, std::max(0.0f, length), sigma);
  if (near >= k_opaque_optical_depth) return near;
  const V3f q = p + to_light * length;
  int xa, ya;
  float fx, fy;
  wrap_floor(q.x / m_cell.x - 0.5f, m_nx, 1.0f / float(m_nx), xa, fx);
  wrap_floor(q.y / m_cell.y - 0.5f, m_ny, 1.0f / float(m_ny), ya, fy);
  const int xb = xa + 1 == m_nx ? 0 : xa + 1, yb = ya + 1 == m_ny ? 0 : ya + 1;
  auto tau = [&](int i, int j) { return m_tau[(size_t(k) * m_ny + j) * m_nx + i]; };
  const float far = (tau(xa, ya) * (1 - fx) + tau(xb, ya) * fx) * (1 - fy) +
                    (tau(xa, yb) * (1 - fx) + tau(xb, yb) * fx) * fy;
  return near + far * depth_scale_for(to_light);
}

float TransmittanceCache::depth_scale_for(const V3f& to_light_texture) const {
  if ((to_light_texture.z >= 0.0f) != m_from_above) return -1.0f;
  const float z = std::fabs(to_light_texture.z);
  if (z < 1e-4f) return -1.0f;
  return std::clamp(std::fabs(m_to_light.z) / z, 0.05f, 20.0f);
}

}  // namespace clothbake
