#pragma once
/// The address and texels a bake takes when the user leaves them to it
/// (`clothbake material` with no --address, the panel's "Automatic"), and
/// why, in one line: the whole repeat where it resolves the threads and fits
/// the memory budget, else one block per crossing class. The paper cloth
/// keeps the whole repeat at 32 texels (its bytes unchanged).

#include <cstdint>
#include <optional>
#include <string>

#include "core/material/material_settings.h"
#include "core/material_bake/material_source.h"

namespace clothbake {

/// Texels per crossing side the automatic choice takes per crossing: the
/// 91 x 480-thread overshot of testscenes/wif/real baked there in 4.6 GB
/// where 32 needed 53 GB (docs/design/material.md, "What the bake chooses").
inline constexpr int k_auto_crossing_texels = 8;
/// The fewest it takes before refusing, when 8 does not fit the budget: 4
/// texels still resolve each thread of a crossing twice over
/// (k_min_texels_per_thread).
inline constexpr int k_auto_crossing_min_texels = 4;

/// What the user fixed; an empty field is chosen by plan_material_bake.
struct BakeRequest {
  std::optional<MaterialAddress> address;
  std::optional<int> texels;
};

struct BakePlan {
  MaterialSettings settings;  ///< address and texels resolved
  std::string mode;    ///< "per crossing at 8 texels (37 blocks)", "the whole repeat at 32 texels"
  std::string reason;  ///< why: "as asked", "the whole repeat spans 62 threads: ..."
  std::string why;     ///< one line: mode (reason; the bytes it holds)
  uint64_t fixed_bytes = 0;  ///< material_bake_fixed_bytes of the choice
  bool fits = true;          ///< fixed_bytes within the budget
};

/// Resolves `request` on `settings` for `source` (its repeat `ends` x
/// `picks` threads; 0: unknown) baked on `threads` within `budget_bytes`:
/// - an address the user fixed is kept;
/// - RGB parts: the whole repeat (per crossing needs colour-free parts);
/// - else the whole repeat at the requested texels (the settings' default
///   when none) when it leaves at least k_min_texels_per_thread texels a
///   thread and its fixed bytes fit the budget; otherwise per crossing at
///   the requested texels, or k_auto_crossing_texels, or, when that does
///   not fit and it does, k_auto_crossing_min_texels.
/// `fits` says whether the choice fits the budget; the caller refuses
/// with advice_for_memory when it does not.
BakePlan plan_material_bake(const MaterialSource& source, const MaterialSettings& settings,
                            const BakeRequest& request, int ends, int picks, int threads,
                            uint64_t budget_bytes);

/// A refusal's advice when `plan` does not fit: the first of the address
/// per crossing and fewer texels (8, 4, 2 per crossing) that fits.
struct MemoryAdvice {
  MaterialSettings settings;  ///< the plan's, with the address and texels advised
  /// The flags that give it, its blocks and the bytes it holds ("--address
  /// crossings --texels 4: 37 blocks, the bake holds about 830 MiB"); empty
  /// when none fits.
  std::string text;
};
MemoryAdvice advice_for_memory(const MaterialSource& source, const BakePlan& plan, int threads,
                               uint64_t budget_bytes);

}  // namespace clothbake
