#include "core/material/yarn_colours.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/weave/thread_layout.h"

namespace clothbake {

using Imath::V3f;

YarnPalette palette_of(const ClothSpec& spec) {
  return YarnPalette{spec.warp.color, spec.weft.color, spec.warp.colors, spec.weft.colors};
}

ColourStrip colour_strip(std::span<const float> centres, float repeat_mm,
                         std::span<const V3f> colours, int texels, int levels) {
  ColourStrip strip;
  const int n = int(centres.size());
  const int nc = std::max(1, int(colours.size()));
  strip.repeats = std::lcm(n, nc) / n;
  const int q = strip.repeats;
  const int columns = q * texels;
  const double width = double(repeat_mm) / texels;
  const double span = double(repeat_mm) * q;
  // Thread j of the q repeats (j = -1 and q n wrap around), its centre and colour.
  auto centre = [&](int j) {
    const int w = ((j % n) + n) % n;
    const int rep = (j - w) / n;
    return double(centres[size_t(w)]) + double(rep) * repeat_mm;
  };
  auto colour = [&](int j) {
    const int total = q * n;
    const int w = ((j % total) + total) % total;
    return colours.empty() ? V3f(0.5f) : colours[size_t(w % nc)];
  };
  // Level 0 of one strip: the colour of thread j + offset over each span
  // thread j owns, length-weighted per column.
  auto level0 = [&](int offset) {
    std::vector<double> acc(size_t(columns) * 3, 0.0);
    for (int j = -1; j <= q * n; ++j) {
      const double lo = std::max(0.0, 0.5 * (centre(j - 1) + centre(j)));
      const double hi = std::min(span, 0.5 * (centre(j) + centre(j + 1)));
      if (!(hi > lo)) continue;
      const V3f c = colour(j + offset);
      const int first = std::clamp(int(std::floor(lo / width)), 0, columns - 1);
      const int last = std::clamp(int(std::ceil(hi / width)) - 1, 0, columns - 1);
      for (int i = first; i <= last; ++i) {
        const double overlap = std::min(hi, (i + 1) * width) - std::max(lo, i * width);
        if (!(overlap > 0.0)) continue;
        for (int k = 0; k < 3; ++k) acc[size_t(i) * 3 + k] += overlap / width * double(c[k]);
      }
    }
    std::vector<V3f> out(static_cast<size_t>(columns));
    for (int i = 0; i < columns; ++i)
      out[size_t(i)] = V3f(float(acc[size_t(i) * 3]), float(acc[size_t(i) * 3 + 1]),
                           float(acc[size_t(i) * 3 + 2]));
    return out;
  };
  // The levels above: pairwise averages, so each is the box average of level 0.
  auto pyramid = [&](std::vector<V3f> base) {
    std::vector<std::vector<V3f>> out(size_t(std::max(levels, 1)));
    out[0] = std::move(base);
    for (int m = 1; m < levels; ++m) {
      const std::vector<V3f>& fine = out[size_t(m - 1)];
      std::vector<V3f>& coarse = out[size_t(m)];
      coarse.resize(std::max<size_t>(1, fine.size() / 2));
      if (fine.size() == 1) {
        coarse[0] = fine[0];
        continue;
      }
      for (size_t i = 0; i < coarse.size(); ++i) coarse[i] = 0.5f * (fine[2 * i] + fine[2 * i + 1]);
    }
    return out;
  };
  strip.threads.resize(size_t(q) * size_t(n));
  for (int j = 0; j < q * n; ++j) strip.threads[size_t(j)] = colour(j);
  strip.levels = pyramid(level0(0));
  strip.plus = pyramid(level0(1));
  strip.minus = pyramid(level0(-1));
  return strip;
}

std::vector<float> thread_centres_mm(const ClothSpec& spec, bool warp) {
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout layout = thread_layout(spec, draft, warp);
  std::vector<float> out(size_t(layout.count()));
  for (int i = 0; i < layout.count(); ++i) out[size_t(i)] = layout.centre_mm(i);
  return out;
}

float thread_repeat_mm(const ClothSpec& spec, bool warp) {
  const WeaveDraft draft = draft_of(spec);
  return thread_layout(spec, draft, warp).repeat_mm();
}

YarnColours yarn_colours(const ClothSpec& spec, const YarnPalette& p, int texels, int levels) {
  YarnColours out;
  const std::vector<float> ends = thread_centres_mm(spec, true);
  const std::vector<float> picks = thread_centres_mm(spec, false);
  const float repeat_x = thread_repeat_mm(spec, true), repeat_y = thread_repeat_mm(spec, false);
  const std::vector<V3f> warp = p.warp_colors.empty() ? std::vector<V3f>{p.warp_color} : p.warp_colors;
  const std::vector<V3f> weft = p.weft_colors.empty() ? std::vector<V3f>{p.weft_color} : p.weft_colors;
  out.warp = colour_strip(ends, repeat_x, warp, texels, levels);
  out.weft = colour_strip(picks, repeat_y, weft, texels, levels);
  return out;
}

}  // namespace clothbake
