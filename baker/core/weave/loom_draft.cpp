#include "core/weave/loom_draft.h"

#include <algorithm>
#include <cmath>

namespace clothbake {

std::vector<std::vector<int>> drawdown(const LoomDraft& d) {
  // Per pick, which shafts are listed (rise, or sink): one flag per shaft.
  std::vector<std::vector<int>> up(d.picks, std::vector<int>(d.ends, 0));
  std::vector<unsigned char> listed(size_t(d.shafts) + 1);
  for (int p = 0; p < d.picks; ++p) {
    std::fill(listed.begin(), listed.end(), 0);
    auto list = [&](const std::vector<int>& shafts) {
      for (int s : shafts)
        if (s >= 1 && s <= d.shafts) listed[s] = 1;
    };
    if (d.has_liftplan) {
      if (p < int(d.liftplan.size())) list(d.liftplan[p]);
    } else if (p < int(d.treadling.size())) {
      for (int t : d.treadling[p])
        if (t >= 1 && t <= int(d.tieup.size())) list(d.tieup[t - 1]);
    }
    for (int e = 0; e < d.ends; ++e) {
      if (e >= int(d.threading.size())) continue;
      bool any_shaft = false, any_listed = false;
      for (int s : d.threading[e]) {
        if (s < 1 || s > d.shafts) continue;
        any_shaft = true;
        any_listed = any_listed || listed[s];
      }
      up[p][e] = d.rising_shed ? any_listed : (any_shaft && !any_listed);
    }
  }
  return up;
}

Imath::V3f display_to_linear(const Imath::V3f& value, float lo, float hi) {
  Imath::V3f out;
  for (int c = 0; c < 3; ++c) {
    const double v = std::clamp((double(value[c]) - lo) / (double(hi) - lo), 0.0, 1.0);
    out[c] = float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
  }
  return out;
}

}  // namespace clothbake
