#include "core/material/view_parallax.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/material/cloth_material.h"
#include "core/material/material_bake.h"
#include "core/util/vector_math.h"

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

}  // namespace

/// The steepest view nodes the fit compares: slope 2.75, 70 degrees from the normal.
constexpr float k_fit_max_slope = 2.75f;

ViewParallaxFit fit_view_parallax(const ClothMaterial& m) {
  const std::vector<std::vector<float>> images = view_images(m);
  const int side = m.level_side(0), rows = m.layout().level_rows(0), k = m.view_grid.k;
  // Addressed per crossing: each texel's centre in its block's crossing, and
  // a view node read there through the crossings' index (shade()'s taps).
  std::vector<V2f> centres_mm;
  if (m.addressed()) {
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < side; ++x) {
        const CrossingClasses::Crossing c = m.crossings.representative[size_t(y / side)];
        const ThreadSpan sx = thread_span(*m.warp_threads, c.end);
        const ThreadSpan sy = thread_span(*m.weft_threads, c.pick);
        centres_mm.push_back(V2f(sx.left_mm + (float(x) + 0.5f) / float(side) * sx.width_mm(),
                                 sy.left_mm + (float(y % side) + 0.5f) / float(side) * sy.width_mm()));
      }
  }
  const auto read_addressed = [&](const std::vector<float>& img, float x_mm, float y_mm) {
    const ClothMaterial::Taps t = m.crossing_taps(x_mm, y_mm, 0, 0, nullptr);
    float sum = 0.0f;
    for (int i = 0; i < 4; ++i) sum += t.w[i] * img[t.texel[i]];
    return sum;
  };
  const float texels_per_mm_x = float(side) / m.repeat_mm.x;
  const float texels_per_mm_y = float(side) / m.repeat_mm.y;
  struct Pair {
    int a, b;
    V3f da, db;
  };
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
          // Pairs within k_fit_max_slope of the normal only: nearer the
          // horizon a node's neighbour is a different image (the rays cross
          // several repeats), which no one shift aligns.
          if (material_slope(da).length() > k_fit_max_slope ||
              material_slope(db).length() > k_fit_max_slope)
            continue;
          pairs.push_back({a, b, da, db});
        }
      }
  // Mean over pairs of sum (A(x) - B(x + shift))^2 / sum A(x)^2, with the
  // eye on node a and node b read where parallax_shift_mm says.
  const auto mismatch = [&](float depth_mm) {
    double total = 0.0;
    for (const Pair& p : pairs) {
      const V2f shift = parallax_shift_mm(p.da, p.db, depth_mm, m.optics.depth_scale);
      const std::vector<float>& a = images[size_t(p.a)];
      const std::vector<float>& b = images[size_t(p.b)];
      double diff = 0.0, norm = 0.0;
      if (m.addressed()) {
        for (size_t t = 0; t < centres_mm.size(); ++t) {
          const double va = a[t];
          const double d =
              va - double(read_addressed(b, centres_mm[t].x + shift.x, centres_mm[t].y + shift.y));
          diff += d * d;
          norm += va * va;
        }
        if (norm > 0.0) total += diff / norm;
        continue;
      }
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
          // Texel centres at (x + 0.5) / side of the repeat, as shade() reads.
          const float bx = float(x) + shift.x * texels_per_mm_x;
          const float by = float(y) + shift.y * texels_per_mm_y;
          const double va = a[size_t(y) * side + x];
          const double d = va - double(bilinear(b, side, bx, by));
          diff += d * d;
          norm += va * va;
        }
      if (norm > 0.0) total += diff / norm;
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
