// Woven-cloth volume texture generator: Kimoto & Ohno (c. 1990), section 2;
// PAPER.md s.2 gives this project's reading of the open points.

#include "core/texture/volume_generator.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/util/error.h"
#include "core/util/random.h"
#include "core/weave/cloth_colours.h"
#include "core/weave/ply_twist.h"
#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"

namespace clothbake {

namespace {

using Imath::V3f;
constexpr float k_pi = std::numbers::pi_v<float>;

bool is_uniform(const ClothSpec& spec) {
  return spec.draft.empty() && spec.pattern == k_uniform_pattern;
}


float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

/// Seeded value noise, periodic over the repeat in x and y, two octaves,
/// roughly in [-1, 1]. Periodic so the texture tiles without seams.
class PeriodicNoise {
 public:
  PeriodicNoise(const V3f& size_mm, float scale_mm, uint64_t seed) : m_size(size_mm) {
    m_lx = std::max(1, int(std::lround(size_mm.x / scale_mm)));
    m_ly = std::max(1, int(std::lround(size_mm.y / scale_mm)));
    m_lz = std::max(1, int(std::lround(size_mm.z / scale_mm)));
    // The lattice values are tabulated once: a few thousand hashes instead of
    // sixteen per lookup. A long repeat (a draft of hundreds of threads) has
    // a lattice too large to hold (a 91 x 480 overshot: 10^10 points), so
    // there each value is hashed when needed: the same value either way.
    m_seed = seed;
    m_tabulated = double(m_lx) * m_ly * (m_lz + 1) * 9.0 <= double(k_max_table);
    for (int f = 1; f <= 2 && m_tabulated; ++f) {
      const int lx = m_lx * f, ly = m_ly * f, lz = m_lz * f + 1;
      std::vector<float>& table = m_lattice[f - 1];
      table.resize(size_t(lx) * ly * lz);
      for (int iz = 0; iz < lz; ++iz)
        for (int iy = 0; iy < ly; ++iy)
          for (int ix = 0; ix < lx; ++ix)
            table[(size_t(iz) * ly + iy) * lx + ix] =
                2.0f * unit_float(hash_key(seed, rng_stream::noise, f, ix, iy, iz)) - 1.0f;
    }
  }
  float operator()(const V3f& p_texture) const {
    return (octave(p_texture, 1) + 0.5f * octave(p_texture, 2)) / 1.5f;
  }

 private:
  float octave(const V3f& p, int f) const {
    const int lx = m_lx * f, ly = m_ly * f, lz = m_lz * f;
    const float gx = p.x / m_size.x * lx, gy = p.y / m_size.y * ly;
    const float gz = std::clamp(p.z / m_size.z * lz, 0.0f, float(lz));
    const int x0 = int(std::floor(gx)), y0 = int(std::floor(gy));
    const int z0 = std::min(int(std::floor(gz)), lz - 1);
    const float tx = smoothstep01(gx - x0), ty = smoothstep01(gy - y0), tz = smoothstep01(gz - z0);
    const std::vector<float>& table = m_lattice[f - 1];
    float acc = 0.0f;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int ix = (((x0 + dx) % lx) + lx) % lx, iy = (((y0 + dy) % ly) + ly) % ly;
          const float w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
          const float value =
              m_tabulated ? table[(size_t(z0 + dz) * ly + iy) * lx + ix]
                          : 2.0f * unit_float(hash_key(m_seed, rng_stream::noise, f, ix, iy,
                                                       z0 + dz)) -
                                1.0f;
          acc += w * value;
        }
    return acc;
  }
  static constexpr size_t k_max_table = size_t(1) << 24;  // lattice points of both octaves
  V3f m_size;
  int m_lx, m_ly, m_lz;
  uint64_t m_seed = 0;
  bool m_tabulated = true;
  std::vector<float> m_lattice[2];  // per octave, [z][y][x], z has one extra plane
};

/// The yarn (if any) whose cross-section contains a point, and where in it.
struct YarnHit {
  float r2 = 2.0f;  ///< squared normalised radius in the elliptical cross-section; <= 1 inside
  YarnFamily family = YarnFamily::None;
  int index = 0;              ///< warp end or weft pick (unwrapped)
  V3f axis_texture{0, 0, 0};  ///< unit yarn direction, including the over/under slope
  V3f radial_texture{0, 0,
                     1};  ///< unit direction from the centre line to the point, across the axis
  float polar = 0.0f;     ///< angle of the point around the centre line, normalised ellipse
  float along_mm = 0.0f;  ///< coordinate along the yarn (y for warp, x for weft)
  float ex = 0.0f, ez = 0.0f;  ///< normalised offsets across the yarn and up
  float slope = 0.0f;          ///< dz/ds of the centre line
};

class WeaveModel {
 public:
  explicit WeaveModel(const ClothSpec& spec)
      : m_spec(spec),
        m_draft(draft_of(spec)),
        m_geom(weave_geometry(spec)),
        m_ends(thread_layout(spec, m_draft, true)),
        m_picks(thread_layout(spec, m_draft, false)) {}

  /// Finds the yarn containing p_texture, preferring the one it lies deepest in.
  YarnHit hit(const V3f& p_texture) const {
    YarnHit best;
    // Evenly spaced threads: the three nearest by division, in the order the
    // generator always took them (ties keep the first, so the order is bytes).
    // Uneven: the centre at or before the point and its neighbours; a thread
    // may be up to twice its spacing wide, so two and three on either side.
    float t, gap;
    if (m_ends.uniform()) {
      const int c0 = int(std::floor(p_texture.x / m_spec.warp.spacing_mm));
      for (int c = c0 - 1; c <= c0 + 1; ++c) consider_warp(p_texture, c, best);
    } else {
      const int c0 = m_ends.locate(p_texture.x, t, gap);
      for (int c = c0 - 2; c <= c0 + 3; ++c) consider_warp(p_texture, c, best);
    }
    if (m_picks.uniform()) {
      const int r0 = int(std::floor(p_texture.y / m_spec.weft.spacing_mm));
      for (int r = r0 - 1; r <= r0 + 1; ++r) consider_weft(p_texture, r, best);
    } else {
      const int r0 = m_picks.locate(p_texture.y, t, gap);
      for (int r = r0 - 2; r <= r0 + 3; ++r) consider_weft(p_texture, r, best);
    }
    return best;
  }

  const WeaveGeometry& geometry() const { return m_geom; }
  const ThreadLayout& ends() const { return m_ends; }
  const ThreadLayout& picks() const { return m_picks; }

 private:
  // Centre-line height and slope of a yarn whose crossing states (+1 over,
  // -1 under) are s0 at one crossing and s1 at the next, a fraction t of the
  // `spacing` between them on; half-cosine blend.
  void path(float t, float s0, float s1, float spacing, float& z_mm, float& slope) const {
    const float blend = 0.5f * (1.0f - std::cos(k_pi * t));
    z_mm = m_geom.z_mid_mm + m_geom.amplitude_mm * (s0 + (s1 - s0) * blend);
    slope = m_geom.amplitude_mm * (s1 - s0) * 0.5f * k_pi * std::sin(k_pi * t) / spacing;
  }

  void consider_warp(const V3f& p, int end, YarnHit& best) const {
    const YarnSpec& y = m_spec.warp;
    const float x_c = m_ends.centre_mm(end);
    const float ex = (p.x - x_c) / (0.5f * m_ends.width_mm(end));
    if (ex * ex > 1.0f) return;  // outside this end's width: skip the path
    float t, gap;
    const int pick = m_picks.locate(p.y, t, gap);
    const float s0 = m_draft.warp_up(pick, end) ? 1.0f : -1.0f;
    const float s1 = m_draft.warp_up(pick + 1, end) ? 1.0f : -1.0f;
    float z_c, slope;
    path(t, s0, s1, gap, z_c, slope);
    const float ez = (p.z - z_c) / (0.5f * y.thickness_mm);
    const float r2 = ex * ex + ez * ez;
    if (r2 > 1.0f || r2 >= best.r2) return;
    best.r2 = r2;
    best.family = YarnFamily::Warp;
    best.index = end;
    best.ex = ex;
    best.ez = ez;
    best.slope = slope;
    best.along_mm = p.y;
  }

  void consider_weft(const V3f& p, int pick, YarnHit& best) const {
    const YarnSpec& y = m_spec.weft;
    const float y_c = m_picks.centre_mm(pick);
    const float ey = (p.y - y_c) / (0.5f * m_picks.width_mm(pick));
    if (ey * ey > 1.0f) return;
    float t, gap;
    const int end = m_ends.locate(p.x, t, gap);
    // The weft is over exactly where the warp is under.
    const float s0 = m_draft.warp_up(pick, end) ? -1.0f : 1.0f;
    const float s1 = m_draft.warp_up(pick, end + 1) ? -1.0f : 1.0f;
    float z_c, slope;
    path(t, s0, s1, gap, z_c, slope);
    const float ez = (p.z - z_c) / (0.5f * y.thickness_mm);
    const float r2 = ey * ey + ez * ez;
    if (r2 > 1.0f || r2 >= best.r2) return;
    best.r2 = r2;
    best.family = YarnFamily::Weft;
    best.index = pick;
    best.ex = ey;
    best.ez = ez;
    best.slope = slope;
    best.along_mm = p.x;
  }

 public:
  /// Fills the frame of a hit (axis, radial direction, polar angle): needed
  /// once per cell, not per sub-cell point.
  void complete(YarnHit& h) const {
    const bool warp = h.family == YarnFamily::Warp;
    const YarnSpec& y = warp ? m_spec.warp : m_spec.weft;
    const float width_mm = warp ? m_ends.width_mm(h.index) : m_picks.width_mm(h.index);
    const float across_mm = h.ex * 0.5f * width_mm, up_mm = h.ez * 0.5f * y.thickness_mm;
    h.axis_texture = (warp ? V3f(0.0f, 1.0f, h.slope) : V3f(1.0f, 0.0f, h.slope)).normalized();
    h.radial_texture =
        radial(warp ? V3f(across_mm, 0.0f, up_mm) : V3f(0.0f, across_mm, up_mm), h.axis_texture);
    h.polar = std::atan2(h.ez, h.ex);
  }

 private:
  static V3f radial(V3f d, const V3f& axis) {
    d -= axis * d.dot(axis);
    const float len = d.length();
    if (len < 1e-9f) {  // on the centre line: any direction across the axis will do
      V3f up(0, 0, 1);
      up -= axis * up.dot(axis);
      return up.normalized();
    }
    return d / len;
  }

  const ClothSpec& m_spec;
  WeaveDraft m_draft;
  WeaveGeometry m_geom;
  ThreadLayout m_ends, m_picks;
};

/// Unit vector rotated away from `t` by `angle` radians toward azimuth `phi`.
V3f perturb(const V3f& t, float angle, float phi) {
  const V3f helper = std::fabs(t.x) < 0.9f ? V3f(1, 0, 0) : V3f(0, 1, 0);
  const V3f b1 = t.cross(helper).normalized();
  const V3f b2 = t.cross(b1);
  const V3f dir = b1 * std::cos(phi) + b2 * std::sin(phi);
  return (t * std::cos(angle) + dir * std::sin(angle)).normalized();
}

}  // namespace

WeaveGeometry weave_geometry(const ClothSpec& spec) {
  const WeaveDraft draft = draft_of(spec);
  WeaveGeometry g;
  g.amplitude_mm = spec.crimp * (spec.warp.thickness_mm + spec.weft.thickness_mm) / 4.0f;
  const float half_max = 0.5f * std::max(spec.warp.thickness_mm, spec.weft.thickness_mm);
  const ThreadLayout ends = thread_layout(spec, draft, true), picks = thread_layout(spec, draft, false);
  g.size_mm = V3f(ends.repeat_mm(), picks.repeat_mm(), 2.0f * (g.amplitude_mm + half_max));
  g.z_mid_mm = 0.5f * g.size_mm.z;
  return g;
}

uint64_t estimated_volume_bytes(const ClothSpec& spec) {
  const ResolutionSpec r = resolved_resolution(spec);
  // Computed in floating point first so absurd resolutions cannot overflow.
  const double cells =
      double(std::max(r.cells_x, 0)) * std::max(r.cells_y, 0) * std::max(r.layers, 0);
  const double bytes = cells * sizeof(Cell) + 4096.0;
  return bytes > 1.8e19 ? UINT64_MAX : uint64_t(bytes);
}

// About 130 lines, kept whole: the per-cell pass of the generator (PAPER.md
// s.2: yarn, density, fibre direction, shading), in one place so the order
// of its random draws, which fixes every byte of the texture, stays visible.
VolumeTexture generate_volume(const ClothSpec& spec, uint64_t memory_budget_bytes) {
  validate(spec);
  const uint64_t need = estimated_volume_bytes(spec);
  if (need > memory_budget_bytes) {
    const ResolutionSpec r = resolved_resolution(spec);
    throw InputError("resolution",
                     std::to_string(r.cells_x) + " x " + std::to_string(r.cells_y) + " x " +
                         std::to_string(r.layers) + " cells need an estimated " +
                         std::to_string(need / (1024 * 1024)) + " MiB, over the memory budget of " +
                         std::to_string(memory_budget_bytes / (1024 * 1024)) + " MiB");
  }

  const WeaveModel weave(spec);
  const WeaveGeometry& geom = weave.geometry();
  const ResolutionSpec res = resolved_resolution(spec);
  VolumeTexture volume(res.cells_x, res.cells_y, res.layers, geom.size_mm);
  if (is_uniform(spec)) {
    Cell c;
    c.density = spec.density.core;
    c.tangent = V3f(1.0f, 0.0f, 0.0f);
    c.diffuse = spec.warp.color * spec.shading.diffuse_top;
    c.specular = spec.shading.specular_top;
    c.exponent = spec.shading.exponent;
    c.family = YarnFamily::Warp;
    for (int k = 0; k < res.layers; ++k)
      for (int j = 0; j < res.cells_y; ++j)
        for (int i = 0; i < res.cells_x; ++i) volume.at(i, j, k) = c;
    return volume;
  }
  const V3f cell_mm = volume.cell_size_mm();
  // Every random choice repeats with the weave, not with its colours: a
  // colour sequence spanning q weave repeats tiles the same cells q times
  // (so a colour-free material of the weave is this cloth's, recoloured).
  const Imath::V2f weave_mm = weave_repeat_mm(spec);
  const int qx = std::max(1, int(std::lround(geom.size_mm.x / weave_mm.x)));
  const int qy = std::max(1, int(std::lround(geom.size_mm.y / weave_mm.y)));
  const int weave_cells_x = res.cells_x / qx, weave_cells_y = res.cells_y / qy;
  const int weave_ends = weave.ends().count() / qx, weave_picks = weave.picks().count() / qy;
  const PeriodicNoise noise(V3f(weave_mm.x, weave_mm.y, geom.size_mm.z),
                            spec.density.noise_scale_mm, spec.seed);
  const int ss = res.supersample;
  const float inv_samples = 1.0f / float(ss * ss * ss);
  const float spread_rad = spec.angle_spread_deg * k_pi / 180.0f;

  const PlyTwist ply(spec, weave_mm);
  static_assert(uint64_t(YarnFamily::Warp) == 1 && uint64_t(YarnFamily::Weft) == 2,
                "PlyTwist keys its draws by these numbers: the same cloth, the same bytes");

  tbb::parallel_for(tbb::blocked_range<int>(0, res.layers * res.cells_y), [&](const auto& rows) {
    for (int row = rows.begin(); row != rows.end(); ++row) {
      const int k = row / res.cells_y, j = row % res.cells_y;
      for (int i = 0; i < res.cells_x; ++i) {
        // Step 1: rho as the occupied fraction over s^3 sub-cell points; the
        // most central hit decides the cell's yarn.
        float rho_sum = 0.0f;
        YarnHit central;
        // The noise varies over noise_scale_mm (several cells): sampled once,
        // at the cell centre.
        const V3f centre_texture((i + 0.5f) * cell_mm.x, (j + 0.5f) * cell_mm.y,
                                 (k + 0.5f) * cell_mm.z);
        const float grain =
            std::max(0.0f, 1.0f + spec.density.noise_amplitude * noise(centre_texture));
        for (int sz = 0; sz < ss; ++sz)
          for (int sy = 0; sy < ss; ++sy)
            for (int sx = 0; sx < ss; ++sx) {
              const V3f p_texture((i + (sx + 0.5f) / ss) * cell_mm.x,
                                  (j + (sy + 0.5f) / ss) * cell_mm.y,
                                  (k + (sz + 0.5f) / ss) * cell_mm.z);
              const YarnHit h = weave.hit(p_texture);
              if (h.family == YarnFamily::None) continue;
              const DensitySpec& d = spec.density;
              const float profile = d.edge + (d.core - d.edge) * std::pow(1.0f - h.r2, d.falloff);
              const float height = p_texture.z / geom.size_mm.z;  // 1 at the top face
              const float depth = 1.0f + (d.top_factor - 1.0f) * smoothstep01(height);
              rho_sum += std::min(1.0f, profile * depth * grain);
              if (h.r2 < central.r2) central = h;
            }
        Cell& cell = volume.at(i, j, k);
        cell.density = std::clamp(rho_sum * inv_samples, 0.0f, 1.0f);
        if (cell.density <= 0.0f || central.family == YarnFamily::None) {
          cell = Cell{};
          continue;
        }
        cell.family = central.family;
        weave.complete(central);

        // Step 2: the fibre tangent. Which of the two bundles the point is in
        // turns with the ply phase along the yarn; bundle 0 runs at +twist,
        // bundle 1 at -twist (base vectors v_V / v_H), then a random rotation.
        const bool warp = central.family == YarnFamily::Warp;
        const YarnSpec& yarn = warp ? spec.warp : spec.weft;
        const ThreadLayout& layout = warp ? weave.ends() : weave.picks();
        const int yarn_id = layout.wrap(central.index);  // its colour
        const int weave_yarn = yarn_id % (warp ? weave_ends : weave_picks);  // its random phase
        const float phase = ply.phase(warp, weave_yarn, central.along_mm);
        float rel = std::fmod(central.polar - phase, 2.0f * k_pi);
        if (rel < 0.0f) rel += 2.0f * k_pi;
        const float bundle_sign = rel < k_pi ? 1.0f : -1.0f;
        const float twist = yarn.twist_deg * k_pi / 180.0f;
        const V3f across = central.radial_texture.cross(central.axis_texture).normalized();
        V3f tangent =
            (central.axis_texture * std::cos(twist) + across * (bundle_sign * std::sin(twist)))
                .normalized();
        const int iw = i % weave_cells_x, jw = j % weave_cells_y;
        const uint64_t cell_key = hash_key(spec.seed, rng_stream::spread, iw, jw, k);
        const float u1 = std::max(unit_float(mix64(cell_key)), 1e-7f);
        const float u2 = unit_float(mix64(cell_key + 1));
        const float u3 = unit_float(mix64(cell_key + 2));
        const float gauss = std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * k_pi * u2);
        tangent = perturb(tangent, spread_rad * gauss, 2.0f * k_pi * u3);
        cell.tangent = tangent;

        // Step 3: shading coefficients, more specular on top, more diffuse
        // below, with seeded variation.
        const ShadingSpec& s = spec.shading;
        const float h = (k + 0.5f) / res.layers;
        const uint64_t shade_key = hash_key(spec.seed, rng_stream::shade, iw, jw, k);
        const float v1 = 2.0f * unit_float(mix64(shade_key)) - 1.0f;
        const float v2 = 2.0f * unit_float(mix64(shade_key + 1)) - 1.0f;
        cell.specular = std::clamp((s.specular_bottom + (s.specular_top - s.specular_bottom) * h) *
                                       (1.0f + s.variation * v1),
                                   0.0f, 1.0f);
        const float dscale =
            (s.diffuse_bottom + (s.diffuse_top - s.diffuse_bottom) * h) * (1.0f + s.variation * v2);
        for (int c = 0; c < 3; ++c)
          cell.diffuse[c] = std::clamp(layout.color(yarn_id)[c] * dscale, 0.0f, 1.0f);
        cell.exponent = s.exponent;
      }
    }
  });
  return volume;
}

}  // namespace clothbake
