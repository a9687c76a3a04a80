#include "core/material/cloth_material.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/material/view_parallax.h"
#include "core/util/vector_math.h"

namespace clothbake {

namespace {
using Imath::V3f;

/// Catmull-Rom weights of the four nodes around t in [0, 1).
void catmull_rom_weights(float t, float* w) {
  const float t2 = t * t, t3 = t2 * t;
  w[0] = 0.5f * (-t3 + 2.0f * t2 - t);
  w[1] = 0.5f * (3.0f * t3 - 5.0f * t2 + 2.0f);
  w[2] = 0.5f * (-3.0f * t3 + 4.0f * t2 + t);
  w[3] = 0.5f * (t3 - t2);
}
}  // namespace

void ClothMaterial::allocate() {
  const int n_levels = layout().levels();
  coefficients.assign(size_t(n_levels), {});
  coefficients_next.assign(colour_parts() ? size_t(n_levels) : 0, {});
  alpha.assign(size_t(n_levels), {});
  const size_t views = size_t(view_count());
  for (int m = 0; m < n_levels; ++m) {
    const size_t texels = layout().level_texels(m);
    coefficients[m].assign(views * texels * size_t(max_rank), V3f(0.0f));
    if (colour_parts())
      coefficients_next[m].assign(views * texels * size_t(max_rank), Imath::V2f(0.0f));
    alpha[m].assign(views * texels, 0.0f);
  }
  light_factors.assign(views * size_t(light_count()) * size_t(max_rank), 0.0f);
  rank.assign(views, 0);
  error.assign(views, 0.0f);
}

void ClothMaterial::build_mips() {
  const size_t views = size_t(view_count());
  const size_t r = size_t(max_rank);
  const MaterialLayout lay = layout();
  for (int m = 1; m < levels(); ++m) {
    const int side = lay.level_side(m), fine = lay.level_side(m - 1);
    const size_t n_fine = lay.level_texels(m - 1), n = lay.level_texels(m);
    for (size_t v = 0; v < views; ++v)
      for (int y = 0; y < lay.level_rows(m); ++y)
        for (int x = 0; x < side; ++x) {
          const size_t t = size_t(y) * side + x;
          const size_t f[4] = {size_t(2 * y) * fine + 2 * x, size_t(2 * y) * fine + 2 * x + 1,
                               size_t(2 * y + 1) * fine + 2 * x,
                               size_t(2 * y + 1) * fine + 2 * x + 1};
          const float* a = alpha[m - 1].data() + v * n_fine;
          alpha[m][v * n + t] = 0.25f * ((a[f[0]] + a[f[1]]) + (a[f[2]] + a[f[3]]));
          for (size_t k = 0; k < r; ++k) {
            const V3f* c = coefficients[m - 1].data() + v * n_fine * r + k;
            coefficients[m][(v * n + t) * r + k] =
                0.25f * ((c[f[0] * r] + c[f[1] * r]) + (c[f[2] * r] + c[f[3] * r]));
            if (colour_parts()) {
              const Imath::V2f* e = coefficients_next[m - 1].data() + v * n_fine * r + k;
              coefficients_next[m][(v * n + t) * r + k] =
                  0.25f * ((e[f[0] * r] + e[f[1] * r]) + (e[f[2] * r] + e[f[3] * r]));
            }
          }
        }
  }
}

void ClothMaterial::set_cloth(const ClothSpec& spec, const YarnPalette& p) {
  cloth = spec;
  palette = p;
  colours = colours_of(p);
  const WeaveDraft draft = draft_of(spec);
  warp_threads = std::make_shared<const ThreadLayout>(thread_layout(spec, draft, true));
  weft_threads = std::make_shared<const ThreadLayout>(thread_layout(spec, draft, false));
  crossings = addressed() ? crossing_classes(spec, settings.stencil, settings.phase_bins)
                          : CrossingClasses{};
}

YarnColours ClothMaterial::colours_of(const YarnPalette& p) const {
  return yarn_colours(cloth, p, texels(), layout().levels());
}

V3f ClothMaterial::material_from_texture(const V3f& d) const {
  return V3f(d.x, d.y, d.z / optics.depth_scale).normalized();
}

V3f ClothMaterial::local_from_material(const V3f& d) const {
  if (optics.aspect == 1.0f) return d;  // the same bits a material without a stretch always had
  const float s = std::sqrt(optics.aspect);
  return V3f(d.x * s, d.y / s, d.z).normalized();
}

V3f ClothMaterial::texture_from_material(const V3f& d) const {
  return V3f(d.x, d.y, d.z * optics.depth_scale).normalized();
}

V3f ClothMaterial::texel_radiance(int level, int view, int node, int x, int y) const {
  const size_t side = size_t(level_side(level));
  const size_t r = size_t(max_rank);
  const V3f* c = coefficients[level].data() +
                 ((size_t(view) * layout().level_texels(level)) + size_t(y) * side + x) * r;
  const float* f = light_factors.data() + (size_t(view) * light_count() + node) * r;
  V3f sum(0.0f);
  for (int k = 0; k < rank[view]; ++k) sum += c[k] * f[k];
  return sum;
}

float ClothMaterial::texel_alpha(int level, int view, int x, int y) const {
  const size_t side = size_t(level_side(level));
  return alpha[level][size_t(view) * layout().level_texels(level) + size_t(y) * side + x];
}

ClothMaterial::LightNodes ClothMaterial::light_nodes(const Light& light) const {
  const DirectionGrid::Footprint lf = light_grid.locate(light.to_light);
  const int kl = light_grid.k;
  LightNodes ln;
  ln.irradiance = light.irradiance;
  if (light_filter == LightFilter::Bilinear || kl < 3) {
    ln.count = 4;
    ln.node[0] = light_grid.node_index(lf.side, lf.i0, lf.j0);
    ln.node[1] = light_grid.node_index(lf.side, lf.i1, lf.j0);
    ln.node[2] = light_grid.node_index(lf.side, lf.i0, lf.j1);
    ln.node[3] = light_grid.node_index(lf.side, lf.i1, lf.j1);
    ln.w[0] = (1 - lf.fx) * (1 - lf.fy), ln.w[1] = lf.fx * (1 - lf.fy);
    ln.w[2] = (1 - lf.fx) * lf.fy, ln.w[3] = lf.fx * lf.fy;
    return ln;
  }
  // Catmull-Rom in i and j over nodes i0 - 1 .. i0 + 2, clamped to the grid.
  float wx[4], wy[4];
  catmull_rom_weights(lf.fx, wx);
  catmull_rom_weights(lf.fy, wy);
  ln.count = 16;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      const int i = std::clamp(lf.i0 - 1 + a, 0, kl - 1), j = std::clamp(lf.j0 - 1 + b, 0, kl - 1);
      ln.node[b * 4 + a] = light_grid.node_index(lf.side, i, j);
      ln.w[b * 4 + a] = wx[a] * wy[b];
    }
  return ln;
}

// Whole repeat: texel taps counted over the colours' repeat (q repeats; q =
// 1 for RGB), the material's texel the tap's modulo its side; a tap's
// column and row index the level's colour strips.
ClothMaterial::Taps ClothMaterial::repeat_taps(float x_mm, float y_mm, int m, int v,
                                               const YarnColours* yarn) const {
  const bool parts = colour_parts();
  const int side = level_side(m);
  const int cols = parts ? int(yarn->warp.levels[size_t(m)].size()) : side;
  const int rows = parts ? int(yarn->weft.levels[size_t(m)].size()) : side;
  int ca, ra;
  float fx, fy;
  wrap_floor(x_mm / repeat_mm.x * float(side) - 0.5f, cols, 1.0f / float(cols), ca, fx);
  wrap_floor(y_mm / repeat_mm.y * float(side) - 0.5f, rows, 1.0f / float(rows), ra, fy);
  const int cb = ca + 1 == cols ? 0 : ca + 1, rb = ra + 1 == rows ? 0 : ra + 1;
  const int xa = ca % side, xb = cb % side, ya = ra % side, yb = rb % side;
  const size_t base = size_t(v) * size_t(side) * side;
  Taps t;
  t.texel[0] = base + size_t(ya) * side + xa, t.texel[1] = base + size_t(ya) * side + xb;
  t.texel[2] = base + size_t(yb) * side + xa, t.texel[3] = base + size_t(yb) * side + xb;
  t.w[0] = (1 - fx) * (1 - fy), t.w[1] = fx * (1 - fy), t.w[2] = (1 - fx) * fy, t.w[3] = fx * fy;
  t.column[0] = ca, t.column[1] = cb, t.row[0] = ra, t.row[1] = rb;
  return t;
}

namespace {
/// Where `coord_mm` lies among a family's threads: the owning thread
/// (unwrapped index) and the fraction of the way across the span it owns
/// (between the midpoints to its neighbours' centres).
void locate_in_span(const ThreadLayout& threads, float coord_mm, int& owner, float& fraction) {
  float t, gap;
  const int i = threads.locate(coord_mm, t, gap);
  owner = t < 0.5f ? i : i + 1;
  const float left = 0.5f * (threads.centre_mm(owner - 1) + threads.centre_mm(owner));
  const float right = 0.5f * (threads.centre_mm(owner) + threads.centre_mm(owner + 1));
  fraction = std::clamp((coord_mm - left) / std::max(right - left, 1e-12f), 0.0f, 0.999999f);
}

/// A tap of a level with `side` texels per crossing: the crossing (counted
/// over `threads` threads, wrapped) and the texel inside it.
void split_tap(int tap, int side, int threads, int& crossing, int& local) {
  const int c = tap >= 0 ? tap / side : -((-tap + side - 1) / side);
  local = tap - c * side;
  crossing = ((c % threads) + threads) % threads;
}
}  // namespace

// Per crossing: each crossing spans `side` texels of level m whatever its
// width, so bilinear taps are counted in crossings and texels, and each tap
// reads the block of its own crossing's class. Crossings are counted over
// the colours' repeat (a per-thread colour sequence longer than the weave's)
// so that a tap's column and row index the per-thread colours.
ClothMaterial::Taps ClothMaterial::crossing_taps(float x_mm, float y_mm, int m, int v,
                                                 const YarnColours* yarn) const {
  const int side = level_side(m);
  const int ends = crossings.ends, picks = crossings.picks;
  const int cols = colour_parts() && yarn ? int(yarn->warp.threads.size()) : ends;
  const int rows = colour_parts() && yarn ? int(yarn->weft.threads.size()) : picks;
  int e, p;
  float fe, fp;
  locate_in_span(*warp_threads, x_mm, e, fe);
  locate_in_span(*weft_threads, y_mm, p, fp);
  const float gx = (float(e) + fe) * float(side) - 0.5f, gy = (float(p) + fp) * float(side) - 0.5f;
  const int tx = int(std::floor(gx)), ty = int(std::floor(gy));
  const float fx = gx - float(tx), fy = gy - float(ty);
  Taps t;
  int lx[2], ly[2];
  for (int a = 0; a < 2; ++a) {
    split_tap(tx + a, side, cols, t.column[a], lx[a]);
    split_tap(ty + a, side, rows, t.row[a], ly[a]);
  }
  const size_t per_view = layout().level_texels(m);
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 2; ++a) {
      const int block = crossings.at(t.column[a] % ends, t.row[b] % picks);
      t.texel[b * 2 + a] =
          size_t(v) * per_view + (size_t(block) * side + size_t(ly[b])) * side + size_t(lx[a]);
    }
  t.w[0] = (1 - fx) * (1 - fy), t.w[1] = fx * (1 - fy), t.w[2] = (1 - fx) * fy, t.w[3] = fx * fy;
  return t;
}

namespace {
/// The light nodes of `lights` (each light's nodes and weights) folded into
/// one RGB weight per component of view node `v`, weights[k], k < rank[v].
void fold_lights(const ClothMaterial& mat, int v, std::span<const ClothMaterial::LightNodes> nodes,
                 V3f* weights) {
  const size_t r = size_t(mat.max_rank);
  const size_t n_nodes = size_t(mat.light_count());
  const int rk = mat.rank[v];
  std::fill(weights, weights + rk, V3f(0.0f));
  for (const ClothMaterial::LightNodes& ln : nodes) {
    // The light's nodes folded into one scalar per component first (a
    // contiguous loop over k), then its RGB irradiance applied once.
    float folded[k_max_components];
    std::fill(folded, folded + rk, 0.0f);
    for (int n = 0; n < ln.count; ++n) {
      if (ln.w[n] == 0.0f) continue;
      const float* f = mat.light_factors.data() + (size_t(v) * n_nodes + ln.node[n]) * r;
      const float w = ln.w[n];
      for (int k = 0; k < rk; ++k) folded[k] += w * f[k];
    }
    for (int k = 0; k < rk; ++k) weights[k] += ln.irradiance * folded[k];
  }
}

/// What a colour-free lookup of view node v reads its yarn colours from: the
/// colours, and the side its ray runs toward across the threads (its
/// neighbours' colours are those of the owner + 1 or - 1).
struct ViewColours {
  const YarnColours* yarn = nullptr;
  V3f ray{0.0f};
  const std::vector<std::vector<V3f>>* warp_next = nullptr;
  const std::vector<std::vector<V3f>>* weft_next = nullptr;
};

/// Tap t of `taps` at level m of view node v (rank rk) under the folded
/// light `weights`: RGB, or for colour-free parts each part's light times
/// its colour, S + W * warp(x) + F * weft(y) and the next threads' likewise.
V3f tap_radiance(const ClothMaterial& mat, const V3f* weights, int rk, int m,
                 const ClothMaterial::Taps& taps, int t, const ViewColours& vc) {
  const size_t r = size_t(mat.max_rank);
  const V3f* coeff = mat.coefficients[m].data() + taps.texel[t] * r;
  V3f sum(0.0f);
  if (!vc.yarn) {
    for (int k = 0; k < rk; ++k) sum += coeff[k] * weights[k];
    return sum;
  }
  const Imath::V2f* next = mat.coefficients_next[m].data() + taps.texel[t] * r;
  V3f s(0.0f), wp(0.0f), fp(0.0f), wn(0.0f), fn(0.0f);
  for (int k = 0; k < rk; ++k) {
    s += weights[k] * coeff[k].x;
    wp += weights[k] * coeff[k].y;
    fp += weights[k] * coeff[k].z;
    wn += weights[k] * next[k].x;
    fn += weights[k] * next[k].y;
  }
  const int col = taps.column[t & 1], row = taps.row[t >> 1];
  const YarnColours& yarn = *vc.yarn;
  if (mat.addressed()) {
    // A block's texel lies in one crossing: its end's and pick's
    // colours, and those of the threads its view ray runs toward.
    const std::vector<V3f>& wc = yarn.warp.threads;
    const std::vector<V3f>& fc = yarn.weft.threads;
    const int nw = int(wc.size()), nf = int(fc.size());
    const int wnext = vc.ray.x >= 0.0f ? 1 : -1, fnext = vc.ray.y >= 0.0f ? 1 : -1;
    return s + wp * wc[size_t(col)] + fp * fc[size_t(row)] +
           wn * wc[size_t((col + wnext + nw) % nw)] + fn * fc[size_t((row + fnext + nf) % nf)];
  }
  return s + wp * yarn.warp.levels[size_t(m)][size_t(col)] +
         fp * yarn.weft.levels[size_t(m)][size_t(row)] +
         wn * (*vc.warp_next)[size_t(m)][size_t(col)] +
         fn * (*vc.weft_next)[size_t(m)][size_t(row)];
}
}  // namespace

// The lookup's three interpolations: light nodes folded into per-component
// weights first (light_nodes), then levels, texels and view nodes.
MarchResult ClothMaterial::shade(float x_mm, float y_mm, float footprint_texels, const V3f& to_eye,
                                 std::span<const Light> lights, const YarnColours* yarn) const {
  MarchResult out;
  const bool parts = colour_parts();
  if (parts && !yarn) yarn = &colours;
  const int n_levels = levels();
  const float level =
      std::clamp(std::log2(std::max(footprint_texels, 1.0f)), 0.0f, float(n_levels - 1));
  const int m0 = std::min(int(level), n_levels - 1), m1 = std::min(m0 + 1, n_levels - 1);
  const float fm = level - float(m0);
  const DirectionGrid::Footprint vf = view_grid.locate(to_eye);
  const int views[4] = {
      view_grid.node_index(vf.side, vf.i0, vf.j0), view_grid.node_index(vf.side, vf.i1, vf.j0),
      view_grid.node_index(vf.side, vf.i0, vf.j1), view_grid.node_index(vf.side, vf.i1, vf.j1)};
  const float wv[4] = {(1 - vf.fx) * (1 - vf.fy), vf.fx * (1 - vf.fy), (1 - vf.fx) * vf.fy,
                       vf.fx * vf.fy};
  // Light nodes: each light's nodes and weights, shared by the views.
  std::array<LightNodes, k_max_march_lights> nodes;
  size_t n_lights = 0;
  for (const Light& light : lights) {
    if (n_lights == nodes.size()) break;
    if (!(light.irradiance.x > 0 || light.irradiance.y > 0 || light.irradiance.z > 0)) continue;
    nodes[n_lights++] = light_nodes(light);
  }
  V3f weights[k_max_components];  // per component: the lights folded in
  V3f radiance(0.0f);
  float alpha_sum = 0.0f;
  for (int c = 0; c < 4; ++c) {
    if (wv[c] == 0.0f) continue;
    const int v = views[c];
    // A material with no parallax depth skips the node's direction (a
    // decode and a normalise per view node per lookup).
    const Imath::V2f shift = parallax_depth_mm == 0.0f
                                 ? Imath::V2f(0.0f)
                                 : parallax_shift_mm(to_eye, view_grid.node_direction(v),
                                                     parallax_depth_mm, optics.depth_scale);
    ViewColours vc;
    if (parts) {
      vc.yarn = yarn;
      vc.ray = -view_grid.bake_direction(v);
      vc.warp_next = vc.ray.x >= 0.0f ? &yarn->warp.plus : &yarn->warp.minus;
      vc.weft_next = vc.ray.y >= 0.0f ? &yarn->weft.plus : &yarn->weft.minus;
    }
    fold_lights(*this, v, std::span(nodes.data(), n_lights), weights);
    for (int mi = 0; mi < 2; ++mi) {
      const int m = mi == 0 ? m0 : m1;
      const float wm = mi == 0 ? 1.0f - fm : fm;
      if (wm == 0.0f) continue;
      const Taps taps = addressed() ? crossing_taps(x_mm + shift.x, y_mm + shift.y, m, v, yarn)
                                    : repeat_taps(x_mm + shift.x, y_mm + shift.y, m, v, yarn);
      const float w = wv[c] * wm;
      for (int t = 0; t < 4; ++t) {
        if (taps.w[t] == 0.0f) continue;
        const V3f sum = tap_radiance(*this, weights, rank[v], m, taps, t, vc);
        radiance += sum * (w * taps.w[t]);
        alpha_sum += alpha[m][taps.texel[t]] * (w * taps.w[t]);
      }
    }
  }
  // Catmull-Rom weights can be negative: no negative light.
  out.radiance =
      V3f(std::max(radiance.x, 0.0f), std::max(radiance.y, 0.0f), std::max(radiance.z, 0.0f));
  out.transmittance = std::clamp(1.0f - alpha_sum, 0.0f, 1.0f);
  return out;
}

}  // namespace clothbake
