#include "core/texture/crossings.h"

#include <cmath>

#include "core/weave/thread_layout.h"
#include "core/weave/weave.h"

namespace clothbake {

Image crossing_tops(const VolumeTexture& volume, const ClothSpec& spec) {
  const WeaveDraft draft = draft_of(spec);
  const ThreadLayout ends = thread_layout(spec, draft, true);
  const ThreadLayout picks = thread_layout(spec, draft, false);
  const Imath::V3f cell = volume.cell_size_mm();
  Image image(ends.count(), picks.count(), 4);
  for (int p = 0; p < picks.count(); ++p)
    for (int e = 0; e < ends.count(); ++e) {
      const int i = int(std::floor(ends.centre_mm(e) / cell.x));
      const int j = int(std::floor(picks.centre_mm(p) / cell.y));
      float* px = image.at(e, p);
      for (int k = volume.nz() - 1; k >= 0; --k) {
        const Cell& c = volume.at(i, j, k);
        if (c.density <= 0.0f) continue;
        px[0] = c.diffuse.x;
        px[1] = c.diffuse.y;
        px[2] = c.diffuse.z;
        px[3] = float(c.family);
        break;
      }
    }
  return image;
}

}  // namespace clothbake
