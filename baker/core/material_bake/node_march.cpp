#include "core/material_bake/node_march.h"

#include <cmath>
#include <numbers>

#include "core/geometry/direction_grid.h"
#include "core/util/random.h"
#include "core/weave/cloth_colours.h"

namespace clothbake {

namespace {
using Imath::V3f;
constexpr float k_inv_4pi = 0.25f / std::numbers::pi_v<float>;
}  // namespace

void FiberLightTable::build(const FiberShader& shader, std::span<const V3f> to_light_local,
                            const V3f& to_eye_local, int k) {
  m_k = k;
  m_lights = to_light_local.size();
  m_diffuse.assign(size_t(k) * k * m_lights, 0.0f);
  m_specular.assign(m_diffuse.size(), 0.0f);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const V3f tangent =
          hemi_oct_decode(Imath::V2f(float(i) / float(k - 1), float(j) / float(k - 1)));
      const size_t row = (size_t(j) * k + i) * m_lights;
      for (size_t l = 0; l < m_lights; ++l) {
        const FiberResponse f = shader.eval(tangent, to_light_local[l], to_eye_local, 0);
        m_diffuse[row + l] = f.diffuse;
        m_specular[row + l] = f.specular;
      }
    }
}

void FiberLightTable::eval(const V3f& tangent, float* diffuse, float* specular) const {
  // Even in the tangent: the upper hemisphere's node of -t where t.z < 0.
  const Imath::V2f uv = hemi_oct_encode(tangent.z < 0.0f ? -tangent : tangent);
  const float gx = uv.x * float(m_k - 1), gy = uv.y * float(m_k - 1);
  const int i0 = std::min(int(gx), m_k - 2), j0 = std::min(int(gy), m_k - 2);
  const float fx = gx - float(i0), fy = gy - float(j0);
  const size_t rows[4] = {
      (size_t(j0) * m_k + i0) * m_lights, (size_t(j0) * m_k + i0 + 1) * m_lights,
      (size_t(j0 + 1) * m_k + i0) * m_lights, (size_t(j0 + 1) * m_k + i0 + 1) * m_lights};
  const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  const float* d[4] = {&m_diffuse[rows[0]], &m_diffuse[rows[1]], &m_diffuse[rows[2]],
                       &m_diffuse[rows[3]]};
  const float* s[4] = {&m_specular[rows[0]], &m_specular[rows[1]], &m_specular[rows[2]],
                       &m_specular[rows[3]]};
  for (size_t l = 0; l < m_lights; ++l) {
    diffuse[l] = w[0] * d[0][l] + w[1] * d[1][l] + w[2] * d[2][l] + w[3] * d[3][l];
    specular[l] = w[0] * s[0][l] + w[1] * s[1][l] + w[2] * s[2][l] + w[3] * s[3][l];
  }
}

namespace {
/// A cell's reflection toward every light node, per unit irradiance: from the
/// tabulated response, from the per-cell cache (deterministic models), or
/// from the fibre model itself (the direct ellipsoid, seeded per sample).
void reflect_all_lights(const NodeMarchInput& in, const Cell& cell, int shaded, bool cacheable,
                        V3f* reflect, NodeMarchScratch& scratch, NodeMarchCounts& counts,
                        const Cell* cells) {
  const size_t n_lights = in.to_light_local.size();
  const V3f tangent_local = V3f(cell.tangent.x * in.sqrt_aspect, cell.tangent.y / in.sqrt_aspect,
                                cell.tangent.z / in.depth_scale)
                                .normalized();
  // RGB, or the colour-free parts: the specular response, then the diffuse
  // one in the slot of the cell's yarn family.
  const float diffuse_part = cell.diffuse.x * (1.0f / k_neutral_albedo);
  const V3f diffuse_rgb = !in.colour_parts
                              ? cell.diffuse
                              : V3f(0.0f, cell.family == YarnFamily::Warp ? diffuse_part : 0.0f,
                                    cell.family == YarnFamily::Weft ? diffuse_part : 0.0f);
  const V3f specular_rgb = !in.colour_parts ? V3f(cell.specular) : V3f(cell.specular, 0.0f, 0.0f);
  if (in.shading == ShadingMode::Isotropic) {
    for (size_t l = 0; l < n_lights; ++l) reflect[l] = in.isotropic_albedo * k_inv_4pi;
  } else if (in.fiber_table) {
    scratch.diffuse.resize(n_lights);
    scratch.specular.resize(n_lights);
    in.fiber_table->eval(tangent_local, scratch.diffuse.data(), scratch.specular.data());
    for (size_t l = 0; l < n_lights; ++l)
      reflect[l] = diffuse_rgb * scratch.diffuse[l] + specular_rgb * scratch.specular[l];
  } else if (cacheable) {
    const size_t c = size_t(&cell - cells);
    float* r = scratch.response.data() + c * n_lights * 2;
    if (scratch.tag[c] != scratch.view_tag) {
      for (size_t l = 0; l < n_lights; ++l) {
        const FiberResponse f =
            in.shader->eval(tangent_local, in.to_light_local[l], in.to_eye_local, 0);
        r[2 * l] = f.diffuse, r[2 * l + 1] = f.specular;
      }
      scratch.tag[c] = scratch.view_tag;
      counts.fiber_evaluations += n_lights;
    }
    for (size_t l = 0; l < n_lights; ++l)
      reflect[l] = diffuse_rgb * r[2 * l] + specular_rgb * r[2 * l + 1];
  } else {
    for (size_t l = 0; l < n_lights; ++l) {
      const FiberResponse f = in.shader->eval(tangent_local, in.to_light_local[l], in.to_eye_local,
                                              hash_key(in.seed, uint64_t(shaded)));
      reflect[l] = diffuse_rgb * f.diffuse + specular_rgb * f.specular;
    }
    counts.fiber_evaluations += n_lights;
  }
}
}  // namespace

// The same march as march_view_ray (the skeleton of sample_march.h), so the
// two agree sample for sample; tests/core/material_bake/material_bake_test.cpp checks it.
float march_view_ray_all_lights(const NodeMarchInput& in, V3f* radiance, NodeMarchScratch& scratch,
                                NodeMarchCounts& counts, V3f* radiance_next) {
  const VolumeTexture& volume = *in.volume;
  const size_t n_lights = in.to_light_local.size();
  scratch.reflect.resize(n_lights);
  scratch.transmittance.resize(n_lights);
  V3f* reflect = scratch.reflect.data();
  float* t_light = scratch.transmittance.data();
  // The per-cell cache (NodeMarchScratch) holds for deterministic models only.
  // With a fibre table the cache is never read: not allocated (it holds
  // cells x lights x 2 floats, 60 GB for a 48-thread WIF at 32 cells a thread).
  const bool cacheable = in.shading == ShadingMode::Fiber && scratch.view_tag != 0 &&
                         in.shader->kind() != FiberModelKind::Ellipsoid && !in.fiber_table;
  const Cell* cells = volume.cells().data();
  if (cacheable && scratch.tag.size() != volume.cell_count()) {
    scratch.tag.assign(volume.cell_count(), 0);
    scratch.response.assign(volume.cell_count() * n_lights * 2, 0.0f);
  }
  // Colour-free parts: whether the current cell is of the sample's own
  // thread (its yarn's centre line is the nearest to the cell's centre).
  V3f* target = radiance;
  const V3f cell_mm = volume.cell_size_mm();
  const int nx = volume.nx(), ny = volume.ny();
  auto shade_cell = [&](const Cell& cell, int shaded) {
    reflect_all_lights(in, cell, shaded, cacheable, reflect, scratch, counts, cells);
    if (in.colour_parts && radiance_next) {
      const size_t c = size_t(&cell - cells);
      const int i = int(c % size_t(nx)), j = int((c / size_t(nx)) % size_t(ny));
      const bool own = cell.family == YarnFamily::Warp
                           ? in.warp_threads->owner((float(i) + 0.5f) * cell_mm.x) == in.own_end
                           : in.weft_threads->owner((float(j) + 0.5f) * cell_mm.y) == in.own_pick;
      target = own ? radiance : radiance_next;
    }
  };
  auto light_sample = [&](const V3f& p_texture, float weight) {
    in.fields->transmittances(p_texture, t_light);
    for (size_t l = 0; l < n_lights; ++l) target[l] += reflect[l] * (t_light[l] * weight);
  };
  const SampleMarchResult r = march_samples(in, shade_cell, light_sample);
  counts.samples += uint64_t(r.samples);
  return r.transmittance;
}

}  // namespace clothbake
