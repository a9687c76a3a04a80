#include "core/material_bake/light_fields.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/march/light_transmittance.h"
#include "core/util/vector_math.h"

namespace clothbake {

namespace {
using Imath::V3f;

/// Cells a sample's march through its own layer crosses at most.
constexpr int k_layer_march_cells = 64;

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

LightFieldMethod LightFieldSet::resolve(LightFieldMethod method, const VolumeTexture& volume,
                                        float sigma, int supersample) {
  if (method != LightFieldMethod::Auto) return method;
  float rho_max = 0.0f;
  for (const Cell& c : volume.cells()) rho_max = std::max(rho_max, c.density);
  const V3f cell = volume.cell_size_mm();
  const float edge = std::max({cell.x, cell.y, cell.z}) / float(std::max(1, supersample));
  return sigma * rho_max * edge > k_layer_march_cell_depth ? LightFieldMethod::LayerMarch
                                                           : LightFieldMethod::Interpolated;
}

size_t LightFieldSet::bytes_for(const VolumeTexture& volume, int lights, int s,
                                LightFieldMethod method) {
  return bytes_for_window(volume, volume.nx(), volume.ny(), lights, s, method);
}

LightFieldSet LightFieldSet::build(const VolumeTexture& volume, std::span<const V3f> to_light,
                                   float sigma, int supersample, LightFieldMethod method) {
  const VolumeTexture fine = refine(volume, std::max(1, supersample));
  if (method == LightFieldMethod::LayerMarch) return build_faces(fine, to_light, sigma);
  LightFieldSet set = shaped_like(fine, to_light.size());
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

LightFieldSet LightFieldSet::shaped_like(const VolumeTexture& fine, size_t lights) {
  LightFieldSet set;
  set.m_nx = fine.nx();
  set.m_ny = fine.ny();
  set.m_nz = fine.nz();
  set.m_lights = int(lights);
  set.m_spacing = fine.cell_size_mm();
  set.m_thickness = fine.size_mm().z;
  return set;
}

LightFieldSet LightFieldSet::build_faces(const VolumeTexture& fine, std::span<const V3f> to_light,
                                         float sigma) {
  LightFieldSet set = shaped_like(fine, to_light.size());
  set.m_method = LightFieldMethod::LayerMarch;
  set.m_sigma = sigma;
  const size_t L = to_light.size();
  const size_t layer = size_t(set.m_nx) * set.m_ny;
  set.m_rho.resize(layer * size_t(set.m_nz));
  for (size_t c = 0; c < set.m_rho.size(); ++c) set.m_rho[c] = fine.cells()[c].density;
  set.m_light.resize(L);
  for (size_t l = 0; l < L; ++l) {
    const V3f& d = to_light[l];
    LightStep& st = set.m_light[l];
    st.from_above = d.z >= 0.0f;
    // 1 / |d.z|: the path length per millimetre of height; a light in the
    // plane (never met by the nodes, which stop short of the horizon) is
    // held at a long but finite path.
    st.path_per_height = 1.0f / std::max(std::fabs(d.z), 1e-3f);
    st.dir_x = d.x;
    st.dir_y = d.y;
    st.inv_abs_x = 1.0f / std::max(std::fabs(d.x), 1e-6f);
    st.inv_abs_y = 1.0f / std::max(std::fabs(d.y), 1e-6f);
  }
  set.m_tau.assign(layer * size_t(set.m_nz + 1) * L, 0.0f);
  for (size_t l = 0; l < L; ++l) {
    const TransmittanceCache cache = TransmittanceCache::build(fine, to_light[l], sigma);
    // Each face plane's depth, at the cell columns' centres: marched exactly
    // through the half layer toward the light, then the cached depth at that
    // layer's centre plane (march_then_lookup). The face the light enters by
    // is 0.
    tbb::parallel_for(0, (set.m_nz + 1) * set.m_ny, [&](int row) {
      const int kz = row / set.m_ny, j = row % set.m_ny;
      for (int i = 0; i < set.m_nx; ++i) {
        const V3f p((float(i) + 0.5f) * set.m_spacing.x, (float(j) + 0.5f) * set.m_spacing.y,
                    float(kz) * set.m_spacing.z);
        set.m_tau[((size_t(kz) * set.m_ny + j) * set.m_nx + i) * L + l] =
            cache.march_then_lookup(fine, p, to_light[l], sigma);
      }
    });
  }
  return set;
}

size_t LightFieldSet::bytes_for_window(const VolumeTexture& volume, int cells_x, int cells_y,
                                       int lights, int s, LightFieldMethod method) {
  const size_t columns =
      size_t(std::min(cells_x, volume.nx())) * s * size_t(std::min(cells_y, volume.ny())) * s;
  const size_t nz = size_t(volume.nz()) * s;
  // Interpolated: nz layer centres + 2 faces per light. Layer march: nz + 1
  // faces per light, and every cell's density.
  if (method == LightFieldMethod::LayerMarch)
    return columns * ((nz + 1) * size_t(lights) + nz) * sizeof(float);
  return columns * (nz + 2) * size_t(lights) * sizeof(float);
}

LightFieldSet LightFieldSet::build_window(const VolumeTexture& volume, int x0, int y0, int cells_x,
                                          int cells_y, std::span<const V3f> to_light, float sigma,
                                          int supersample, LightFieldMethod method) {
  if (cells_x >= volume.nx() && cells_y >= volume.ny())
    return build(volume, to_light, sigma, supersample, method);
  // An axis the window spans whole stays the volume's own, from cell 0.
  if (cells_x >= volume.nx()) x0 = 0, cells_x = volume.nx();
  if (cells_y >= volume.ny()) y0 = 0, cells_y = volume.ny();
  const V3f cell = volume.cell_size_mm();
  VolumeTexture window(cells_x, cells_y, volume.nz(),
                       V3f(float(cells_x) * cell.x, float(cells_y) * cell.y, volume.size_mm().z));
  for (int k = 0; k < volume.nz(); ++k)
    for (int j = 0; j < cells_y; ++j)
      for (int i = 0; i < cells_x; ++i) window.at(i, j, k) = volume.at(x0 + i, y0 + j, k);
  LightFieldSet set = build(window, to_light, sigma, supersample, method);
  set.m_origin = Imath::V2f(float(x0) * cell.x, float(y0) * cell.y);
  set.m_window = Imath::V2f(window.size_mm().x, window.size_mm().y);
  set.m_repeat = Imath::V2f(volume.size_mm().x, volume.size_mm().y);
  return set;
}

void LightFieldSet::depths(const V3f& p_volume, float* depth) const {
  const V3f p = in_window(p_volume);
  if (m_method == LightFieldMethod::LayerMarch)
    depths_layer_march(p, depth);
  else
    depths_interpolated(p, depth);
}

V3f LightFieldSet::in_window(const V3f& p_volume) const {
  V3f p = p_volume;
  if (m_repeat.x > 0.0f) {
    // Into the window's frame, from the repeat's copy nearest its centre.
    for (int a = 0; a < 2; ++a) {
      float d = p[a] - m_origin[a];
      d -= m_repeat[a] * std::round((d - 0.5f * m_window[a]) / m_repeat[a]);
      p[a] = d;
    }
  }
  return p;
}

void LightFieldSet::depths_interpolated(const V3f& p, float* depth) const {
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
  const float w[8] = {(1 - fx) * (1 - fy) * (1 - fz),
                      fx * (1 - fy) * (1 - fz),
                      (1 - fx) * fy * (1 - fz),
                      fx * fy * (1 - fz),
                      (1 - fx) * (1 - fy) * fz,
                      fx * (1 - fy) * fz,
                      (1 - fx) * fy * fz,
                      fx * fy * fz};
  for (size_t l = 0; l < L; ++l) depth[l] = 0.0f;
  for (int n = 0; n < 8; ++n) {
    if (w[n] == 0.0f) continue;
    const float* src = c[n];
    const float wn = w[n];
    for (size_t l = 0; l < L; ++l) depth[l] += wn * src[l];
  }
}

void LightFieldSet::depths_layer_march(const V3f& p, float* depth) const {
  // The sample's own fine cell: its density holds from p to the cell's face
  // toward the light, exactly as the view march and the shadow march take it.
  int ic, jc;
  float ux, uy;
  wrap_floor(p.x / m_spacing.x, m_nx, 1.0f / float(m_nx), ic, ux);
  wrap_floor(p.y / m_spacing.y, m_ny, 1.0f / float(m_ny), jc, uy);
  const int kc = std::clamp(int(std::floor(p.z / m_spacing.z)), 0, m_nz - 1);
  const float rise_up = std::max(0.0f, float(kc + 1) * m_spacing.z - p.z);
  const float rise_down = std::max(0.0f, p.z - float(kc) * m_spacing.z);
  // Toward each light: the cell's own density up to the face the light
  // enters the cell's layer by, then that face's depth where the light's ray
  // crosses it (bilinear between the columns' centres).
  const size_t L = size_t(m_lights);
  const float inv_sx = 1.0f / m_spacing.x, inv_sy = 1.0f / m_spacing.y;
  const float inv_nx = 1.0f / float(m_nx), inv_ny = 1.0f / float(m_ny);
  for (size_t l = 0; l < L; ++l) {
    const LightStep& st = m_light[l];
    const float t = (st.from_above ? rise_up : rise_down) * st.path_per_height;
    const int kz = st.from_above ? kc + 1 : kc;
    int xa, ya;
    float fx, fy;
    wrap_floor((p.x + st.dir_x * t) * inv_sx - 0.5f, m_nx, inv_nx, xa, fx);
    wrap_floor((p.y + st.dir_y * t) * inv_sy - 0.5f, m_ny, inv_ny, ya, fy);
    const int xb = xa + 1 == m_nx ? 0 : xa + 1, yb = ya + 1 == m_ny ? 0 : ya + 1;
    const float* row_a = m_tau.data() + ((size_t(kz) * m_ny + ya) * m_nx) * L + l;
    const float* row_b = m_tau.data() + ((size_t(kz) * m_ny + yb) * m_nx) * L + l;
    // Bilinear in transmittance, not in depth: across a yarn's shadow edge
    // the face's depth jumps by several within one field cell, and depth
    // interpolated there puts the shadow's exp(-depth) on the lit side
    // (darker on the mean); transmittance interpolated keeps the edge's mean
    // light. Equal corners (a homogeneous slab) give their depth exactly.
    const float d00 = row_a[xa * L], d10 = row_a[xb * L], d01 = row_b[xa * L], d11 = row_b[xb * L];
    float face;
    if (d00 == d10 && d00 == d01 && d00 == d11) {
      face = d00;
    } else {
      const float lit = (std::exp(-d00) * (1 - fx) + std::exp(-d10) * fx) * (1 - fy) +
                        (std::exp(-d01) * (1 - fx) + std::exp(-d11) * fx) * fy;
      face = lit > 0.0f ? -std::log(lit) : k_opaque_optical_depth;
    }
    // Through the sample's layer to that face, cell by cell (a 2-D DDA: the
    // layer's cells are constant in z), as the shadow march takes it.
    float along = 0.0f, t_now = 0.0f, lx = ux * m_spacing.x, ly = uy * m_spacing.y;
    int i = ic, j = jc;
    // At most k_layer_march_cells cells: a node 1 degree above the horizon
    // crosses 57 x a layer's height sideways (93 cells of a 2.12 mm yarn at
    // 2 points per cell edge); past the cap the path is not counted (its
    // transmittance is that node's least concern: lit at 1 degree).
    for (int n = 0; n < k_layer_march_cells && t_now < t; ++n) {
      const float tx = st.dir_x > 0.0f   ? (m_spacing.x - lx) * st.inv_abs_x
                       : st.dir_x < 0.0f ? lx * st.inv_abs_x
                                         : 1e30f;
      const float ty = st.dir_y > 0.0f   ? (m_spacing.y - ly) * st.inv_abs_y
                       : st.dir_y < 0.0f ? ly * st.inv_abs_y
                                         : 1e30f;
      const float dt = std::min({tx, ty, t - t_now});
      along += m_rho[(size_t(kc) * m_ny + j) * m_nx + i] * dt;
      t_now += dt;
      lx += st.dir_x * dt;
      ly += st.dir_y * dt;
      if (dt == tx) {
        i = st.dir_x > 0.0f ? (i + 1 == m_nx ? 0 : i + 1) : (i == 0 ? m_nx - 1 : i - 1);
        lx = st.dir_x > 0.0f ? 0.0f : m_spacing.x;
      } else if (dt == ty) {
        j = st.dir_y > 0.0f ? (j + 1 == m_ny ? 0 : j + 1) : (j == 0 ? m_ny - 1 : j - 1);
        ly = st.dir_y > 0.0f ? 0.0f : m_spacing.y;
      }
    }
    depth[l] = face + m_sigma * along;
  }
}

void LightFieldSet::transmittances(const V3f& p, float* t) const {
  depths(p, t);
  for (int l = 0; l < m_lights; ++l) t[l] = TransmittanceCache::transmittance(t[l]);
}

}  // namespace clothbake
