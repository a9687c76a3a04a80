#pragma once
/// What lies on top at each crossing of a generated volume: the check that
/// the volume wove what the draft says (tests/cli/wif_real.sh compares it
/// with an independent reading of the file).

#include "core/texture/volume_texture.h"
#include "core/util/image.h"
#include "core/weave/cloth_spec.h"

namespace clothbake {

/// ends x picks pixels, RGBA: pixel (x = e, y = p) (row p, top row first, so
/// NOT drawn as a weaver draws) is end e+1 at pick p+1. RGB = the diffuse of
/// the top-most cell with rho > 0 in the column through the crossing's
/// centre, A = its yarn family (1 warp, 2 weft, 0 nothing there).
Image crossing_tops(const VolumeTexture& volume, const ClothSpec& spec);

}  // namespace clothbake
