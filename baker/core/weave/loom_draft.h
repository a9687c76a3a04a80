#pragma once
/// A weaver's draft as a loom weaves it: which shafts each warp end is drawn
/// through (the threading), which shafts each pick raises (through a tie-up
/// and treadling, or directly by a liftplan), and whether the listed shafts
/// rise or sink. The drawdown, the 0/1 interlacing a WeaveDraft holds, follows
/// from these (drawdown()). Read from a WIF file by io/wif_reader.h; rules in
/// docs/formats/wif.md.

#include <string>
#include <vector>

#include <Imath/ImathVec.h>

namespace clothbake {

struct LoomDraft {
  int ends = 0;       ///< warp threads, [WARP] Threads
  int picks = 0;      ///< weft threads, [WEFT] Threads
  int shafts = 0;     ///< [WEAVING] Shafts
  int treadles = 0;   ///< [WEAVING] Treadles
  bool rising_shed = true;  ///< the listed shafts rise (false: they sink)
  /// Shafts (1-based) per end (0-based index): end e+1's entry; empty = on no shaft.
  std::vector<std::vector<int>> threading;
  /// Shafts per treadle (0-based index); a treadle with no row ties nothing.
  std::vector<std::vector<int>> tieup;
  /// Treadles (1-based) per pick; empty = no treadle pressed.
  std::vector<std::vector<int>> treadling;
  /// Shafts per pick, used instead of tie-up and treadling when `has_liftplan`.
  std::vector<std::vector<int>> liftplan;
  bool has_liftplan = false;
};

/// The drawdown: rows = picks (row p is pick p+1, at texture y = p spacings),
/// columns = ends; 1 = the warp end is on top. Rising shed: an end is up when
/// one of its shafts is listed for the pick. Sinking shed: the listed shafts
/// sink, an end is up when it is on a shaft and none of its shafts is listed.
/// An end on no shaft is never lifted.
std::vector<std::vector<int>> drawdown(const LoomDraft& draft);

/// A weaving file's display colour (value in [lo, hi] of its palette Range,
/// per channel) as linear albedo: the sRGB transfer function inverted
/// (IEC 61966-2-1), since drafting programs show the numbers on a display.
Imath::V3f display_to_linear(const Imath::V3f& value, float lo, float hi);

}  // namespace clothbake
