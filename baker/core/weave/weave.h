#pragma once
/// Weave drafts (PAPER.md s.2, "which yarn lies on top where").
///
/// A draft is a binary matrix over one weave repeat: rows are weft picks (along
/// texture y), columns are warp ends (along texture x). draft(row, col) = true
/// means the warp end `col` passes OVER the weft pick `row` at that crossing.
/// Warp yarns run along +y, weft yarns along +x.

#include <string>
#include <string_view>
#include <vector>

namespace clothbake {

/// Largest draft, in threads per side (drafts of hundreds are ordinary).
inline constexpr int k_max_draft_threads = 4096;

class WeaveDraft {
 public:
  WeaveDraft() = default;
  /// `rows` x `cols` matrix, row-major. Throws InputError (field "weave.draft")
  /// when empty, ragged, larger than k_max_draft_threads, or not 0/1. A row
  /// or column that never interlaces is a float over or under the whole
  /// repeat: real cloth (an overshot's pattern picks, a selvedge), kept.
  explicit WeaveDraft(std::vector<std::vector<int>> matrix);

  /// Named drafts: "plain", "twill_2_1", "twill_2_2", "satin_5", "satin_8",
  /// "basket_2x2". Throws InputError listing the names when unknown.
  static WeaveDraft named(std::string_view name);
  static const std::vector<std::string>& names();

  int picks() const { return m_rows; }  ///< weft picks per repeat (rows, along y)
  int ends() const { return m_cols; }   ///< warp ends per repeat (columns, along x)
  /// Periodic access: any integer indices wrap into the repeat.
  bool warp_up(int pick, int end) const;
  /// The same drawdown over its smallest repeat: the fewest picks and ends
  /// (divisors of this draft's) that tile it. A WIF holds a whole threading
  /// (214 ends of plain weave, to carry a colour stripe): its weave repeats
  /// every 2 (crossing_neighbourhoods counts over it).
  WeaveDraft smallest_repeat() const;

 private:
  int m_rows = 0, m_cols = 0;
  std::vector<unsigned char> m_up;
};

}  // namespace clothbake
