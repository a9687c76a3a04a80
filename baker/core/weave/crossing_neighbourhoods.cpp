#include "core/weave/crossing_neighbourhoods.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/weave/cloth_colours.h"
#include "core/weave/ply_twist.h"
#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"

namespace clothbake {

namespace {

/// One thread's part of a key: its spacing (the spec's per-thread value, so
/// that equal threads give equal bits; centres are running sums) and its
/// width. A window holds its threads' neighbours too, so the gaps between
/// them are in the key.
void append_thread(std::string& key, const YarnSpec& yarn, const ThreadLayout& layout, int i) {
  const int w = layout.wrap(i);
  const float v[2] = {yarn.spacings_mm.empty() ? yarn.spacing_mm
                                               : yarn.spacings_mm[size_t(w) % yarn.spacings_mm.size()],
                      layout.width_mm(w)};
  key.append(reinterpret_cast<const char*>(v), sizeof v);
}

/// The periodic drawdown over the layouts' repeat (a multiple of the draft's
/// when a spacing or width sequence lengthens it): '1' where the warp is up.
struct Drawdown {
  const WeaveDraft& draft;
  char up(int p, int e) const {
    const int pp = ((p % draft.picks()) + draft.picks()) % draft.picks();
    const int ee = ((e % draft.ends()) + draft.ends()) % draft.ends();
    return draft.warp_up(pp, ee) ? '1' : '0';
  }
};

/// The plus-1 key of crossing (e, p): the three crossings along its end and
/// along its pick, and the spacing and width of the three ends and picks.
void plus1_key(std::string& key, const Drawdown& dd, const ClothSpec& spec,
               const ThreadLayout& ends, const ThreadLayout& picks, int e, int p) {
  key.clear();
  for (int d = -1; d <= 1; ++d) key += dd.up(p + d, e);
  for (int d = -1; d <= 1; ++d) key += dd.up(p, e + d);
  for (int d = -1; d <= 1; ++d) append_thread(key, spec.warp, ends, e + d);
  for (int d = -1; d <= 1; ++d) append_thread(key, spec.weft, picks, p + d);
}

/// The square key of radius r: the (2r + 1)^2 window and its threads.
void square_key(std::string& key, const Drawdown& dd, const ClothSpec& spec,
                const ThreadLayout& ends, const ThreadLayout& picks, int e, int p, int r) {
  key.clear();
  for (int dp = -r; dp <= r; ++dp)
    for (int de = -r; de <= r; ++de) key += dd.up(p + dp, e + de);
  for (int d = -r; d <= r; ++d) append_thread(key, spec.warp, ends, e + d);
  for (int d = -r; d <= r; ++d) append_thread(key, spec.weft, picks, p + d);
}

}  // namespace

CrossingClasses crossing_classes(const ClothSpec& spec, CrossingStencil stencil, int phase_bins) {
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true);
  const ThreadLayout picks = thread_layout(spec, draft, false);
  const Drawdown dd{draft};
  // The ply phase of the yarn on top at a crossing's centre, as the
  // generator draws it (per yarn of the weave repeat, which a spacing or
  // width sequence may repeat q times across the layouts' repeat).
  const Imath::V2f weave_mm = weave_repeat_mm(spec);
  const PlyTwist ply(spec, weave_mm);
  const int weave_ends =
      ends.count() / std::max(1, int(std::lround(ends.repeat_mm() / weave_mm.x)));
  const int weave_picks =
      picks.count() / std::max(1, int(std::lround(picks.repeat_mm() / weave_mm.y)));
  const float bin = 2.0f * std::numbers::pi_v<float> / float(std::max(phase_bins, 1));
  auto top_phase = [&](int e, int p, int& which) {
    const bool warp = dd.up(p, e) == '1';
    const float phase = warp ? ply.phase(true, e % weave_ends, picks.centre_mm(p))
                             : ply.phase(false, p % weave_picks, ends.centre_mm(e));
    const float wrapped = phase - 2.0f * std::numbers::pi_v<float> *
                                      std::floor(phase / (2.0f * std::numbers::pi_v<float>));
    which = std::min(int(wrapped / bin), phase_bins - 1);
    return std::abs(wrapped - (float(which) + 0.5f) * bin);  // off the bin's centre
  };
  CrossingClasses out;
  out.ends = ends.count();
  out.picks = picks.count();
  out.class_of.resize(size_t(out.ends) * size_t(out.picks));
  std::unordered_map<std::string, int> seen;
  std::vector<float> off_centre;  // per class, its representative's
  std::string key;
  for (int p = 0; p < out.picks; ++p)
    for (int e = 0; e < out.ends; ++e) {
      if (stencil == CrossingStencil::Plus1)
        plus1_key(key, dd, spec, ends, picks, e, p);
      else
        square_key(key, dd, spec, ends, picks, e, p, 1);
      float off = 0.0f;
      if (phase_bins > 1) {
        int which = 0;
        off = top_phase(e, p, which);
        key += char(which);
      }
      const auto [it, added] = seen.emplace(key, out.count());
      if (added) {
        out.representative.push_back({e, p});
        off_centre.push_back(off);
      } else if (off < off_centre[size_t(it->second)]) {
        // The crossing nearest its bin's centre stands for the class: its
        // block is then at most half a bin from any member's phase.
        out.representative[size_t(it->second)] = {e, p};
        off_centre[size_t(it->second)] = off;
      }
      out.class_of[size_t(p) * size_t(out.ends) + size_t(e)] = it->second;
    }
  return out;
}

std::vector<CrossingClasses::Crossing> CrossingClasses::members(int b, int n) const {
  std::vector<Crossing> all;
  for (size_t i = 0; i < class_of.size(); ++i)
    if (class_of[i] == b) all.push_back({int(i % size_t(ends)), int(i / size_t(ends))});
  const size_t m = std::min(all.size(), size_t(std::max(n, 1)));
  std::vector<Crossing> out;
  for (size_t i = 0; i < m; ++i) out.push_back(all[i * all.size() / m]);
  // The representative first: the class's first crossing (all[0]), or with
  // phase bins the one nearest its bin's centre, which takes the place of
  // all[0].
  const Crossing r = representative[size_t(b)];
  const auto at = std::find_if(out.begin(), out.end(), [&](const Crossing& c) {
    return c.end == r.end && c.pick == r.pick;
  });
  if (at != out.end())
    std::iter_swap(out.begin(), at);
  else
    out[0] = r;
  return out;
}

NeighbourhoodCounts crossing_neighbourhoods(const ClothSpec& coloured) {
  const ClothSpec spec = colour_free(coloured);
  // colour_free() cuts the drawdown to its smallest repeat (a WIF's plain
  // weave written over 214 ends repeats every 2); the spacing and width
  // sequences may lengthen the layouts' repeat again.
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true);
  const ThreadLayout picks = thread_layout(spec, draft, false);
  NeighbourhoodCounts out;
  out.ends = ends.count();
  out.picks = picks.count();
  // The drawdown over the layouts' repeat (a multiple of the draft's when a
  // spacing or width sequence lengthens it), periodic in both directions.
  const Drawdown dd{draft};
  std::unordered_set<std::string> plus;
  std::array<std::unordered_set<std::string>, 3> square;
  std::string key;
  for (int p = 0; p < out.picks; ++p)
    for (int e = 0; e < out.ends; ++e) {
      plus1_key(key, dd, spec, ends, picks, e, p);
      plus.insert(key);
      for (int r = 1; r <= 3; ++r) {
        square_key(key, dd, spec, ends, picks, e, p, r);
        square[size_t(r - 1)].insert(key);
      }
    }
  out.plus1 = int(plus.size());
  for (int r = 0; r < 3; ++r) out.square[size_t(r)] = int(square[size_t(r)].size());
  return out;
}

}  // namespace clothbake
