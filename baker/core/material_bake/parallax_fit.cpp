#include "core/material_bake/parallax_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/material/view_parallax.h"
#include "core/material_bake/material_sample.h"
#include "core/util/vector_math.h"

namespace clothbake {

using Imath::V2f;
using Imath::V3f;

namespace {

/// Each view node's level-0 image under every light node at once (one
/// scalar per texel: the sum of its channels), empty for rank-0 nodes.
std::vector<std::vector<float>> view_images(const ClothMaterial& m) {
  const int texels = int(m.layout().level_texels(0)), n_nodes = m.light_count();
  const size_t r = size_t(m.max_rank);
  std::vector<std::vector<float>> images(size_t(m.view_count()));
  for (int v = 0; v < m.view_count(); ++v) {
    const int rk = m.rank[size_t(v)];
    if (rk == 0) continue;
    std::vector<float> g(size_t(rk), 0.0f);
    for (int n = 0; n < n_nodes; ++n) {
      const float* f = m.light_factors.data() + (size_t(v) * n_nodes + n) * r;
      for (int k = 0; k < rk; ++k) g[size_t(k)] += f[k];
    }
    std::vector<float>& img = images[size_t(v)];
    img.assign(size_t(texels), 0.0f);
    for (int t = 0; t < texels; ++t) {
      const V3f* c = m.coefficients[0].data() + (size_t(v) * texels + t) * r;
      float sum = 0.0f;
      for (int k = 0; k < rk; ++k) sum += (c[k].x + c[k].y + c[k].z) * g[size_t(k)];
      if (m.colour_parts()) {
        const Imath::V2f* e = m.coefficients_next[0].data() + (size_t(v) * texels + t) * r;
        for (int k = 0; k < rk; ++k) sum += (e[k].x + e[k].y) * g[size_t(k)];
      }
      img[size_t(t)] = sum;
    }
  }
  return images;
}

/// Periodic bilinear read of a side x side image at texel coordinates (x, y).
float bilinear(const std::vector<float>& img, int side, float x, float y) {
  int xa, ya;
  float fx, fy;
  wrap_floor(x, side, 1.0f / float(side), xa, fx);
  wrap_floor(y, side, 1.0f / float(side), ya, fy);
  const int xb = xa + 1 == side ? 0 : xa + 1, yb = ya + 1 == side ? 0 : ya + 1;
  const auto at = [&](int i, int j) { return img[size_t(j) * side + i]; };
  return (1 - fy) * ((1 - fx) * at(xa, ya) + fx * at(xb, ya)) +
         fy * ((1 - fx) * at(xa, yb) + fx * at(xb, yb));
}

/// The steepest view nodes the fit compares: slope 2.75, 70 degrees from the normal.
constexpr float k_fit_max_slope = 2.75f;

/// Addressed per crossing: each level-0 texel's centre (texture mm) in its
/// block's crossing, where a view node is read through the crossings' index
/// (shade()'s taps). Empty for a whole-repeat material.
std::vector<V2f> texel_centres_mm(const ClothMaterial& m) {
  std::vector<V2f> centres_mm;
  if (!m.addressed()) return centres_mm;
  const int side = m.level_side(0), rows = m.layout().level_rows(0);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < side; ++x) {
      const CrossingClasses::Crossing c = m.crossings.representative[size_t(y / side)];
      const ThreadSpan sx = thread_span(*m.warp_threads, c.end);
      const ThreadSpan sy = thread_span(*m.weft_threads, c.pick);
      centres_mm.push_back(
          V2f(sx.left_mm + (float(x) + 0.5f) / float(side) * sx.width_mm(),
              sy.left_mm + (float(y % side) + 0.5f) / float(side) * sy.width_mm()));
    }
  return centres_mm;
}

/// Two neighbouring view nodes and their directions.
struct Pair {
  int a, b;
  V3f da, db;
};

/// The neighbouring view nodes the fit compares: same side, both with an
/// image, both within k_fit_max_slope of the normal (nearer the horizon a
/// node's neighbour is a different image, the rays crossing several
/// repeats, which no one shift aligns).
std::vector<Pair> neighbour_pairs(const ClothMaterial& m,
                                  const std::vector<std::vector<float>>& images) {
  const int k = m.view_grid.k;
  std::vector<Pair> pairs;
  for (int s = 0; s < 2; ++s)
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const int a = m.view_grid.node_index(s, i, j);
        for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
          if (i + di >= k || j + dj >= k) continue;
          const int b = m.view_grid.node_index(s, i + di, j + dj);
          if (images[size_t(a)].empty() || images[size_t(b)].empty()) continue;
          const V3f da = m.view_grid.node_direction(s, i, j);
          const V3f db = m.view_grid.node_direction(s, i + di, j + dj);
          if (material_slope(da).length() > k_fit_max_slope ||
              material_slope(db).length() > k_fit_max_slope)
            continue;
          pairs.push_back({a, b, da, db});
        }
      }
  return pairs;
}

/// sum (A(x) - B(x + shift))^2 / sum A(x)^2 for image `a` against image `b`
/// read `shift_mm` away (0 when A is black). Addressed per crossing, at
/// `centres_mm` through the crossings' index; else at the texel centres, at
/// (x + 0.5) / side of the repeat, as shade() reads.
double relative_mismatch(const ClothMaterial& m, const std::vector<V2f>& centres_mm,
                         const std::vector<float>& a, const std::vector<float>& b,
                         const V2f& shift) {
  double diff = 0.0, norm = 0.0;
  if (m.addressed()) {
    for (size_t t = 0; t < centres_mm.size(); ++t) {
      const ClothMaterial::Taps taps =
          m.crossing_taps(centres_mm[t].x + shift.x, centres_mm[t].y + shift.y, 0, 0, nullptr);
      float read = 0.0f;
      for (int i = 0; i < 4; ++i) read += taps.w[i] * b[taps.texel[i]];
      const double va = a[t];
      const double d = va - double(read);
      diff += d * d;
      norm += va * va;
    }
    return norm > 0.0 ? diff / norm : 0.0;
  }
  const int side = m.level_side(0);
  const float texels_per_mm_x = float(side) / m.repeat_mm.x;
  const float texels_per_mm_y = float(side) / m.repeat_mm.y;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const float bx = float(x) + shift.x * texels_per_mm_x;
      const float by = float(y) + shift.y * texels_per_mm_y;
      const double va = a[size_t(y) * side + x];
      const double d = va - double(bilinear(b, side, bx, by));
      diff += d * d;
      norm += va * va;
    }
  return norm > 0.0 ? diff / norm : 0.0;
}

}  // namespace

ViewParallaxFit fit_view_parallax(const ClothMaterial& m) {
  const std::vector<std::vector<float>> images = view_images(m);
  const std::vector<V2f> centres_mm = texel_centres_mm(m);
  const std::vector<Pair> pairs = neighbour_pairs(m, images);
  // The mean over pairs, with the eye on node a and node b read where
  // parallax_shift_mm says.
  const auto mismatch = [&](float depth_mm) {
    double total = 0.0;
    for (const Pair& p : pairs) {
      const V2f shift = parallax_shift_mm(p.da, p.db, depth_mm, m.optics.depth_scale);
      total += relative_mismatch(m, centres_mm, images[size_t(p.a)], images[size_t(p.b)], shift);
    }
    return pairs.empty() ? 0.0 : total / double(pairs.size());
  };
  ViewParallaxFit fit;
  fit.mismatch_at_zero = fit.mismatch = float(mismatch(0.0f));
  constexpr int steps = 40;
  for (int i = 1; i <= steps; ++i) {
    const float depth = 0.5f * m.repeat_mm.z * float(i) / float(steps);
    const float e = float(mismatch(depth));
    if (e < fit.mismatch) fit = {depth, fit.mismatch_at_zero, e};
  }
  return fit;
}

}  // namespace clothbake
