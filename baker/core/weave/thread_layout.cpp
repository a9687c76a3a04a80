#include "core/weave/thread_layout.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/util/error.h"

namespace clothbake {

int lcm_capped(int a, int b, int cap) {
  const long long l = (long long)a / std::gcd(a, b) * b;
  return l > cap ? 0 : int(l);
}

ThreadLayout::ThreadLayout(const YarnSpec& yarn, int draft_threads, const char* field) {
  const std::string family = field;
  int n = draft_threads;
  const std::pair<size_t, const char*> lists[] = {
      {yarn.colors.size(), "colors"},
      {yarn.spacings_mm.size(), "spacings_mm"},
      {yarn.widths_mm.size(), "widths_mm"}};
  for (const auto& [len, name] : lists) {
    if (len == 0) continue;
    if (len > size_t(k_max_threads_per_repeat))
      throw InputError(family + "." + name, "has " + std::to_string(len) +
                                                " entries, more than the " +
                                                std::to_string(k_max_threads_per_repeat) +
                                                " threads a repeat may have");
    const int next = lcm_capped(n, int(len), k_max_threads_per_repeat);
    if (next == 0)
      throw InputError(family + "." + name,
                       "a sequence of " + std::to_string(len) + " with a repeat of " +
                           std::to_string(n) + " threads makes a repeat longer than " +
                           std::to_string(k_max_threads_per_repeat) +
                           " threads (the least common multiple)");
    n = next;
  }
  m_count = n;
  m_spacing = yarn.spacing_mm;
  m_centre.resize(n);
  m_width.resize(n);
  m_color.resize(n);
  for (int i = 0; i < n; ++i) {
    m_width[i] = yarn.widths_mm.empty() ? yarn.width_mm : yarn.widths_mm[i % yarn.widths_mm.size()];
    m_color[i] = yarn.colors.empty() ? yarn.color : yarn.colors[i % yarn.colors.size()];
  }
  m_uniform = yarn.spacings_mm.empty();
  if (yarn.spacings_mm.empty()) {
    for (int i = 0; i < n; ++i) m_centre[i] = (i + 0.5f) * m_spacing;
    m_repeat_mm = n * m_spacing;
  } else {
    // Thread i's spacing is the gap from its centre to the next one's; the
    // first centre sits half the last gap after x = 0 so the repeat tiles.
    double at = 0.5 * yarn.spacings_mm[(n - 1) % yarn.spacings_mm.size()];
    for (int i = 0; i < n; ++i) {
      m_centre[i] = float(at);
      at += yarn.spacings_mm[i % yarn.spacings_mm.size()];
    }
    m_repeat_mm = float(at - 0.5 * yarn.spacings_mm[(n - 1) % yarn.spacings_mm.size()]);
  }
}

float ThreadLayout::centre_mm(int i) const {
  if (m_uniform || m_centre.empty()) return (i + 0.5f) * m_spacing;
  const int w = wrap(i);
  const int cycles = (i - w) / m_count;
  return m_centre[w] + float(cycles) * m_repeat_mm;
}

int ThreadLayout::locate(float coord_mm, float& t, float& gap_mm) const {
  if (m_uniform) {
    // As the uniform generator always computed it (same bytes).
    const float u = coord_mm / m_spacing - 0.5f;
    const int i = int(std::floor(u));
    t = u - std::floor(u);
    gap_mm = m_spacing;
    return i;
  }
  const float cycles = std::floor(coord_mm / m_repeat_mm);
  const float local = coord_mm - cycles * m_repeat_mm;
  // Last centre <= local; before the first centre it is the previous repeat's last.
  const auto it = std::upper_bound(m_centre.begin(), m_centre.end(), local);
  int i = int(it - m_centre.begin()) - 1;
  const int base = int(cycles) * m_count;
  const float c0 = centre_mm(base + i), c1 = centre_mm(base + i + 1);
  gap_mm = c1 - c0;
  t = std::clamp((coord_mm - c0) / gap_mm, 0.0f, 0.99999994f);
  return base + i;
}

ThreadLayout thread_layout(const ClothSpec& spec, const WeaveDraft& draft, bool warp) {
  return warp ? ThreadLayout(spec.warp, draft.ends(), "warp")
              : ThreadLayout(spec.weft, draft.picks(), "weft");
}

}  // namespace clothbake
