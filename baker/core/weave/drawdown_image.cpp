#include "core/weave/drawdown_image.h"

#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"

namespace clothbake {


void repeat_threads(const ClothSpec& spec, int& ends, int& picks) {
  const WeaveDraft draft = draft_of(spec);
  ends = thread_layout(spec, draft, true).count();
  picks = thread_layout(spec, draft, false).count();
}

Image drawdown_image(const ClothSpec& spec, int block) {
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true);
  const ThreadLayout picks = thread_layout(spec, draft, false);
  Image image(ends.count() * block, picks.count() * block, 3);
  const bool lines = block >= 4;
  for (int p = 0; p < picks.count(); ++p)
    for (int e = 0; e < ends.count(); ++e) {
      const Imath::V3f c = draft.warp_up(p, e) ? ends.color(e) : picks.color(p);
      const int y0 = (picks.count() - 1 - p) * block;  // pick 1 at the bottom
      for (int y = 0; y < block; ++y)
        for (int x = 0; x < block; ++x) {
          const bool edge = lines && (x == block - 1 || y == block - 1);
          float* px = image.at(e * block + x, y0 + y);
          for (int k = 0; k < 3; ++k) px[k] = edge ? 0.25f * c[k] : c[k];
        }
    }
  return image;
}

}  // namespace clothbake
