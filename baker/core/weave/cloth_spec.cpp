#include "core/weave/cloth_spec.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/util/error.h"
#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"

namespace clothbake {

namespace {
void require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw InputError(field, what);
}
void finite_range(float v, float lo, float hi, const std::string& field) {
  require(std::isfinite(v), field, "must be a finite number");
  require(v >= lo && v <= hi, field,
          "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
              std::to_string(v));
}
void positive(float v, const std::string& field) {
  require(std::isfinite(v), field, "must be a finite number");
  require(v > 0.0f, field, "must be greater than 0, got " + std::to_string(v));
}
void validate_yarn(const YarnSpec& y, const std::string& f) {
  positive(y.spacing_mm, f + ".spacing_mm");
  positive(y.width_mm, f + ".width_mm");
  positive(y.thickness_mm, f + ".thickness_mm");
  require(y.width_mm <= 2.0f * y.spacing_mm, f + ".width_mm",
          "must be at most twice spacing_mm (yarns would overlap their second neighbour)");
  for (int c = 0; c < 3; ++c) finite_range(y.color[c], 0.0f, 1.0f, f + ".color");
  finite_range(y.twist_deg, 0.0f, 89.0f, f + ".twist_deg");
  positive(y.ply_pitch_mm, f + ".ply_pitch_mm");
  for (size_t i = 0; i < y.colors.size(); ++i)
    for (int c = 0; c < 3; ++c)
      finite_range(y.colors[i][c], 0.0f, 1.0f, f + ".colors[" + std::to_string(i) + "]");
  for (size_t i = 0; i < y.spacings_mm.size(); ++i)
    positive(y.spacings_mm[i], f + ".spacings_mm[" + std::to_string(i) + "]");
  for (size_t i = 0; i < y.widths_mm.size(); ++i)
    positive(y.widths_mm[i], f + ".widths_mm[" + std::to_string(i) + "]");
  // Each thread at most twice as wide as the gaps either side of it, so a
  // point meets only its neighbours' cross-sections.
  const size_t n = std::max({y.widths_mm.size(), y.spacings_mm.size(), size_t(1)});
  if (!y.widths_mm.empty() || !y.spacings_mm.empty())
    for (size_t i = 0; i < n; ++i) {
      auto spacing = [&](size_t k) {
        return y.spacings_mm.empty() ? y.spacing_mm : y.spacings_mm[k % y.spacings_mm.size()];
      };
      const float w = y.widths_mm.empty() ? y.width_mm : y.widths_mm[i % y.widths_mm.size()];
      const float gap = std::min(spacing(i), spacing(i + n - 1));
      require(w <= 2.0f * gap, f + (y.widths_mm.empty() ? ".width_mm" : ".widths_mm[" + std::to_string(i % y.widths_mm.size()) + "]"),
              "thread " + std::to_string(i + 1) + " is " + std::to_string(w) +
                  " mm wide, more than twice the " + std::to_string(gap) +
                  " mm gap beside it (it would overlap its second neighbour)");
    }
}
}  // namespace

void validate(const ClothSpec& spec) {
  // The draft constructor checks shape and interlacing and names the field.
  if (spec.draft.empty() && spec.pattern == k_uniform_pattern) {
    // no draft: a homogeneous slab
  } else if (spec.draft.empty())
    (void)WeaveDraft::named(spec.pattern);
  else
    (void)WeaveDraft(spec.draft);
  (void)resolved_resolution(spec);  // the repeat's length, refused when too long
  validate_yarn(spec.warp, "warp");
  validate_yarn(spec.weft, "weft");
  finite_range(spec.crimp, 0.0f, 2.0f, "crimp");
  finite_range(spec.angle_spread_deg, 0.0f, 45.0f, "angle_spread_deg");

  const DensitySpec& d = spec.density;
  finite_range(d.core, 1e-6f, 1.0f, "density.core");
  finite_range(d.edge, 0.0f, d.core, "density.edge");
  positive(d.falloff, "density.falloff");
  finite_range(d.top_factor, 1e-6f, 1.0f, "density.top_factor");
  finite_range(d.noise_amplitude, 0.0f, 1.0f, "density.noise_amplitude");
  positive(d.noise_scale_mm, "density.noise_scale_mm");

  const ShadingSpec& s = spec.shading;
  finite_range(s.specular_top, 0.0f, 1.0f, "shading.specular_top");
  finite_range(s.specular_bottom, 0.0f, 1.0f, "shading.specular_bottom");
  finite_range(s.diffuse_top, 0.0f, 1.0f, "shading.diffuse_top");
  finite_range(s.diffuse_bottom, 0.0f, 1.0f, "shading.diffuse_bottom");
  finite_range(s.exponent, 1e-3f, 10000.0f, "shading.exponent");
  finite_range(s.variation, 0.0f, 1.0f, "shading.variation");
  finite_range(s.fiber_aspect, 1.0f, 1000.0f, "shading.fiber_aspect");

  const ResolutionSpec& r = spec.resolution;
  require(r.cells_x >= 0, "resolution.cells_x", "must be at least 1 (or 0: automatic)");
  require(r.cells_y >= 0, "resolution.cells_y", "must be at least 1 (or 0: automatic)");
  require(r.cells_per_thread >= 1 && r.cells_per_thread <= 256, "resolution.cells_per_thread",
          "must be in [1, 256], got " + std::to_string(r.cells_per_thread));
  require(r.layers >= 1, "resolution.layers", "must be at least 1");
  require(r.supersample >= 1 && r.supersample <= 8, "resolution.supersample",
          "must be in [1, 8], got " + std::to_string(r.supersample));
}

WeaveDraft draft_of(const ClothSpec& spec) {
  if (!spec.draft.empty()) return WeaveDraft(spec.draft);
  if (spec.pattern == k_uniform_pattern) return WeaveDraft({{1, 0}, {0, 1}});
  return WeaveDraft::named(spec.pattern);
}

ResolutionSpec resolved_resolution(const ClothSpec& spec) {
  ResolutionSpec r = spec.resolution;
  const bool named = spec.draft.empty();
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true), picks = thread_layout(spec, draft, false);
  // The weave's repeat without its colours: the cells are counted over it,
  // and a colour sequence that spans several of them repeats them, so that
  // colours never change the cells (a colour-free material, cloth_colours.h).
  YarnSpec warp = spec.warp, weft = spec.weft;
  warp.colors.clear();
  weft.colors.clear();
  const ThreadLayout weave_ends(warp, draft.ends(), "warp"), weave_picks(weft, draft.picks(), "weft");
  // A named pattern has 64 cells per repeat of the pattern; a draft gets
  // cells per thread, at least 64 per repeat of the weave.
  auto per_weave = [&](int weave_threads, int draft_threads, int given) -> long long {
    if (given > 0) return given;
    return named ? 64LL * (weave_threads / draft_threads)
                 : std::max(64LL, (long long)r.cells_per_thread * weave_threads);
  };
  auto total = [](long long per_weave_repeat, int threads, int weave_threads) {
    return int(std::min<long long>(per_weave_repeat * (threads / weave_threads), 1 << 30));
  };
  r.cells_x = total(per_weave(weave_ends.count(), draft.ends(), r.cells_x), ends.count(),
                    weave_ends.count());
  r.cells_y = total(per_weave(weave_picks.count(), draft.picks(), r.cells_y), picks.count(),
                    weave_picks.count());
  return r;
}

}  // namespace clothbake
