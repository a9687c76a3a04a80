#include "core/weave/weave.h"

#include <utility>

#include "core/util/error.h"

namespace clothbake {

namespace {
int wrap(int i, int n) { return ((i % n) + n) % n; }

// Satin with `n` harnesses and move `step` (coprime with n, not 1 or n-1):
// one warp float per pick, shifted by `step` ends each pick.
std::vector<std::vector<int>> satin(int n, int step) {
  std::vector<std::vector<int>> m(n, std::vector<int>(n, 0));
  for (int r = 0; r < n; ++r) m[r][wrap(r * step, n)] = 1;
  return m;
}

// Twill `up`/`down`: warp over `up` picks then under `down`, shifted one end per pick.
std::vector<std::vector<int>> twill(int up, int down) {
  int n = up + down;
  std::vector<std::vector<int>> m(n, std::vector<int>(n, 0));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) m[r][c] = wrap(c - r, n) < up ? 1 : 0;
  return m;
}
}  // namespace

WeaveDraft::WeaveDraft(std::vector<std::vector<int>> matrix) {
  const std::string field = "weave.draft";
  if (matrix.empty() || matrix[0].empty())
    throw InputError(field, "the draft is empty; give at least a 2 x 2 matrix of 0 and 1");
  m_rows = static_cast<int>(matrix.size());
  m_cols = static_cast<int>(matrix[0].size());
  if (m_rows > k_max_draft_threads || m_cols > k_max_draft_threads)
    throw InputError(field, "the draft is " + std::to_string(m_rows) + " x " +
                                std::to_string(m_cols) + ", larger than " +
                                std::to_string(k_max_draft_threads) + " x " +
                                std::to_string(k_max_draft_threads));
  m_up.resize(size_t(m_rows) * m_cols);
  for (int r = 0; r < m_rows; ++r) {
    if (static_cast<int>(matrix[r].size()) != m_cols)
      throw InputError(field + "[" + std::to_string(r) + "]",
                       "row has " + std::to_string(matrix[r].size()) + " entries, row 0 has " +
                           std::to_string(m_cols));
    for (int c = 0; c < m_cols; ++c) {
      int v = matrix[r][c];
      if (v != 0 && v != 1)
        throw InputError(
            field + "[" + std::to_string(r) + "][" + std::to_string(c) + "]",
            "entries must be 0 (weft on top) or 1 (warp on top), got " + std::to_string(v));
      m_up[size_t(r) * m_cols + c] = static_cast<unsigned char>(v);
    }
  }
}

const std::vector<std::string>& WeaveDraft::names() {
  static const std::vector<std::string> k_names = {"plain",   "twill_2_1", "twill_2_2",
                                                   "satin_5", "satin_8",   "basket_2x2"};
  return k_names;
}

WeaveDraft WeaveDraft::named(std::string_view name) {
  if (name == "plain") return WeaveDraft({{1, 0}, {0, 1}});
  if (name == "twill_2_1") return WeaveDraft(twill(2, 1));
  if (name == "twill_2_2") return WeaveDraft(twill(2, 2));
  if (name == "satin_5") return WeaveDraft(satin(5, 2));
  if (name == "satin_8") return WeaveDraft(satin(8, 3));
  if (name == "basket_2x2")
    return WeaveDraft({{1, 1, 0, 0}, {1, 1, 0, 0}, {0, 0, 1, 1}, {0, 0, 1, 1}});
  std::string list;
  for (const auto& n : names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("weave.pattern",
                   "unknown weave '" + std::string(name) + "'; expected one of: " + list +
                       ", uniform (a homogeneous slab), or give weave.draft as a matrix");
}

bool WeaveDraft::warp_up(int pick, int end) const {
  return m_up[size_t(wrap(pick, m_rows)) * m_cols + wrap(end, m_cols)] != 0;
}

WeaveDraft WeaveDraft::smallest_repeat() const {
  auto tiles = [&](int picks, int ends) {
    for (int r = 0; r < m_rows; ++r)
      for (int c = 0; c < m_cols; ++c)
        if (warp_up(r, c) != warp_up(r % picks, c % ends)) return false;
    return true;
  };
  int picks = m_rows, ends = m_cols;
  for (int p = 1; p <= m_rows; ++p)
    if (m_rows % p == 0 && tiles(p, m_cols)) {
      picks = p;
      break;
    }
  for (int e = 1; e <= m_cols; ++e)
    if (m_cols % e == 0 && tiles(picks, e)) {
      ends = e;
      break;
    }
  if (picks == m_rows && ends == m_cols) return *this;
  std::vector<std::vector<int>> m(size_t(picks), std::vector<int>(size_t(ends), 0));
  for (int r = 0; r < picks; ++r)
    for (int c = 0; c < ends; ++c) m[size_t(r)][size_t(c)] = warp_up(r, c) ? 1 : 0;
  return WeaveDraft(std::move(m));
}

}  // namespace clothbake
