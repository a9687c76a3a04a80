#pragma once
/// Where each thread of one yarn family lies across one repeat of the cloth,
/// and what it looks like (PAPER.md s.2: the yarns the draft interlaces).
///
/// Warp ends lie along texture x (end 0 first, at x = 0 ... spacing), weft
/// picks along y. The repeat holds the least common multiple of the draft's
/// thread count and the lengths of the per-thread lists (colours, spacings,
/// widths), so a plain weave with a 12-end colour stripe repeats every 12 ends.
/// With every spacing equal, centres are (i + 1/2) spacing exactly as the
/// uniform generator always placed them (same bytes).

#include <vector>

#include <Imath/ImathVec.h>

#include "core/weave/cloth_spec.h"

namespace clothbake {

/// Largest repeat, in threads per family, a cloth may have (the colour
/// sequences' least common multiple included).
inline constexpr int k_max_threads_per_repeat = 4096;

class ThreadLayout {
 public:
  ThreadLayout() = default;
  /// `draft_threads`: ends (or picks) of the draft; `field` names the family
  /// ("warp" or "weft") in errors. Throws InputError when the repeat would
  /// exceed k_max_threads_per_repeat.
  ThreadLayout(const YarnSpec& yarn, int draft_threads, const char* field);

  int count() const { return m_count; }    ///< threads per repeat
  float repeat_mm() const { return m_repeat_mm; }
  bool uniform() const { return m_uniform; }  ///< every spacing equal (widths may differ)
  /// Any integer index wraps into the repeat; centre_mm is unwrapped
  /// (thread count + i lies one repeat further on).
  float centre_mm(int i) const;
  float width_mm(int i) const { return m_width[wrap(i)]; }
  const Imath::V3f& color(int i) const { return m_color[wrap(i)]; }
  /// The thread whose centre is the last at or before `coord_mm` (unwrapped
  /// index) and the fraction t in [0, 1) of the way to the next centre;
  /// `gap_mm` is the distance between those two centres.
  int locate(float coord_mm, float& t, float& gap_mm) const;
  int wrap(int i) const { return ((i % m_count) + m_count) % m_count; }
  /// The thread whose centre is nearest `coord_mm`, wrapped into the repeat:
  /// the thread that owns the point (its span runs to the midpoints).
  int owner(float coord_mm) const {
    float t, gap;
    const int i = locate(coord_mm, t, gap);
    return wrap(t < 0.5f ? i : i + 1);
  }

 private:
  int m_count = 0;
  float m_spacing = 0.0f;  // the uniform spacing
  float m_repeat_mm = 0.0f;
  bool m_uniform = true;
  std::vector<float> m_centre;  // per thread, in [0, repeat)
  std::vector<float> m_width;
  std::vector<Imath::V3f> m_color;
};

/// One family's layout of `spec` over its draft (draft_of(spec)): the
/// warp's ends along x (`warp`), or the weft's picks along y.
ThreadLayout thread_layout(const ClothSpec& spec, const WeaveDraft& draft, bool warp);

/// Least common multiple of a and b (both >= 1), or 0 when it exceeds `cap`.
int lcm_capped(int a, int b, int cap);

}  // namespace clothbake
