#include "core/weave/cloth_colours.h"

#include <cmath>
#include <charconv>
#include <cstddef>
#include <tuple>

#include "core/weave/thread_layout.h"

namespace clothbake {

namespace {
/// Cells over the colour-free repeat with the coloured cloth's cell size.
int scaled_cells(int cells_full, int threads_full, int threads_free) {
  const long long exact = (long long)cells_full * threads_free;
  if (exact % threads_full == 0) return int(exact / threads_full);
  return std::max(1, int(std::lround(double(exact) / double(threads_full))));
}

/// The shortest prefix of `v` that repeats to give it (its length divides
/// v's): a WIF writes one value per thread over its whole threading.
template <class T>
std::vector<T> smallest_period(const std::vector<T>& v) {
  const size_t n = v.size();
  for (size_t p = 1; p < n; ++p) {
    if (n % p != 0) continue;
    bool tiles = true;
    for (size_t i = p; i < n && tiles; ++i) tiles = v[i] == v[i - p];
    if (tiles) return std::vector<T>(v.begin(), v.begin() + std::ptrdiff_t(p));
  }
  return v;
}

std::string text(float v) {  // shortest text that reads back as v
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}
std::string text(const Imath::V3f& v) { return "[" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + "]"; }
std::string text(const std::vector<float>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + text(v[i]);
  return s + "]";
}
std::string text(const std::vector<std::vector<int>>& d) {
  return std::to_string(d.size()) + " x " + std::to_string(d.empty() ? 0 : d[0].size()) +
         " draft";
}
}  // namespace

ClothSpec colour_free(const ClothSpec& spec) {
  const ResolutionSpec full = resolved_resolution(spec);
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true), picks = thread_layout(spec, draft, false);
  ClothSpec out = spec;
  for (YarnSpec* y : {&out.warp, &out.weft}) {
    y->color = Imath::V3f(k_neutral_albedo);
    y->colors.clear();
  }
  // The drawdown over its smallest repeat, written out as the draft: a named
  // pattern becomes its draft, so that a scene naming the pattern and one
  // giving its draft compare equal, and a draft written over several
  // repeats (a WIF writes its whole threading: a plain weave over 214 ends
  // to carry its colour stripes) is cut to one, so that the material does
  // not grow with the colours' repeat. With the per-thread sequences cut to
  // their smallest periods below, the first threads are kept: thread 0
  // stays thread 0 and the cut repeat divides the written one.
  const WeaveDraft weave = draft.smallest_repeat();
  if (out.pattern != k_uniform_pattern || !out.draft.empty()) {
    if (out.draft.empty()) out.pattern = "plain";  // what a spec with a draft carries
    out.draft.assign(size_t(weave.picks()), std::vector<int>(size_t(weave.ends()), 0));
    for (int r = 0; r < weave.picks(); ++r)
      for (int c = 0; c < weave.ends(); ++c) out.draft[r][c] = weave.warp_up(r, c) ? 1 : 0;
  }
  for (YarnSpec* y : {&out.warp, &out.weft}) {
    y->spacings_mm = smallest_period(y->spacings_mm);
    y->widths_mm = smallest_period(y->widths_mm);
  }
  out.draft_source.clear();
  out.draft_program.clear();
  const ThreadLayout free_ends(out.warp, weave.ends(), "warp");
  const ThreadLayout free_picks(out.weft, weave.picks(), "weft");
  out.resolution.cells_x = scaled_cells(full.cells_x, ends.count(), free_ends.count());
  out.resolution.cells_y = scaled_cells(full.cells_y, picks.count(), free_picks.count());
  return out;
}

Imath::V2f weave_repeat_mm(const ClothSpec& spec) {
  // The draft as written, without the colour sequences (colour_free() would
  // also cut it to its smallest repeat).
  YarnSpec warp = spec.warp, weft = spec.weft;
  warp.colors.clear();
  weft.colors.clear();
  const WeaveDraft draft = draft_of(spec);
  return Imath::V2f(ThreadLayout(warp, draft.ends(), "warp").repeat_mm(),
                    ThreadLayout(weft, draft.picks(), "weft").repeat_mm());
}

Imath::V2f colour_free_repeats(const ClothSpec& spec) {
  const ClothSpec free = colour_free(spec);
  const WeaveDraft draft = draft_of(free);
  const Imath::V2f free_mm(ThreadLayout(free.warp, draft.ends(), "warp").repeat_mm(),
                           ThreadLayout(free.weft, draft.picks(), "weft").repeat_mm());
  const Imath::V2f written = weave_repeat_mm(spec);
  return Imath::V2f(std::round(written.x / free_mm.x), std::round(written.y / free_mm.y));
}

ClothDifference first_difference(const ClothSpec& a, const ClothSpec& b) {
  ClothDifference d;
  auto check = [&](const char* field, const auto& x, const auto& y) {
    if (!d.field.empty() || x == y) return;
    d.field = field;
    d.a = text(x);
    d.b = text(y);
  };
  if (a.draft.empty() != b.draft.empty() || (a.draft.empty() && a.pattern != b.pattern)) {
    d.field = "weave.pattern";
    d.a = a.draft.empty() ? a.pattern : "a draft";
    d.b = b.draft.empty() ? b.pattern : "a draft";
  }
  check("weave.draft", a.draft, b.draft);
  for (const auto& [name, ya, yb] : {std::tuple{"warp", &a.warp, &b.warp},
                                     std::tuple{"weft", &a.weft, &b.weft}}) {
    const std::string n = name;
    auto f = [&](const char* key, const auto& x, const auto& y) {
      if (!d.field.empty() || x == y) return;
      d.field = n + "." + key;
      d.a = text(x);
      d.b = text(y);
    };
    f("spacing_mm", ya->spacing_mm, yb->spacing_mm);
    f("width_mm", ya->width_mm, yb->width_mm);
    f("thickness_mm", ya->thickness_mm, yb->thickness_mm);
    f("twist_deg", ya->twist_deg, yb->twist_deg);
    f("ply_pitch_mm", ya->ply_pitch_mm, yb->ply_pitch_mm);
    f("spacings_mm", ya->spacings_mm, yb->spacings_mm);
    f("widths_mm", ya->widths_mm, yb->widths_mm);
    f("color", ya->color, yb->color);
  }
  check("crimp", a.crimp, b.crimp);
  check("angle_spread_deg", a.angle_spread_deg, b.angle_spread_deg);
  check("density.core", a.density.core, b.density.core);
  check("density.edge", a.density.edge, b.density.edge);
  check("density.falloff", a.density.falloff, b.density.falloff);
  check("density.top_factor", a.density.top_factor, b.density.top_factor);
  check("density.noise_amplitude", a.density.noise_amplitude, b.density.noise_amplitude);
  check("density.noise_scale_mm", a.density.noise_scale_mm, b.density.noise_scale_mm);
  check("shading.specular_top", a.shading.specular_top, b.shading.specular_top);
  check("shading.specular_bottom", a.shading.specular_bottom, b.shading.specular_bottom);
  check("shading.diffuse_top", a.shading.diffuse_top, b.shading.diffuse_top);
  check("shading.diffuse_bottom", a.shading.diffuse_bottom, b.shading.diffuse_bottom);
  check("shading.exponent", a.shading.exponent, b.shading.exponent);
  check("shading.variation", a.shading.variation, b.shading.variation);
  check("shading.fiber_aspect", a.shading.fiber_aspect, b.shading.fiber_aspect);
  const ResolutionSpec ra = resolved_resolution(a), rb = resolved_resolution(b);
  check("resolution.cells_x", float(ra.cells_x), float(rb.cells_x));
  check("resolution.cells_y", float(ra.cells_y), float(rb.cells_y));
  check("resolution.layers", float(ra.layers), float(rb.layers));
  check("resolution.supersample", float(ra.supersample), float(rb.supersample));
  if (d.field.empty() && a.seed != b.seed) {
    d.field = "seed";
    d.a = std::to_string(a.seed);
    d.b = std::to_string(b.seed);
  }
  return d;
}

}  // namespace clothbake
