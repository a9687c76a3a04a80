#pragma once
/// The cloth's drawdown as a weaver draws it: one square block per crossing,
/// coloured by the thread on top there, pick 1 at the bottom and end 1 at the
/// left (texture x right, y up: the same way up as the volume's top view).
/// Over the full repeat (the colour sequences' least common multiple).

#include "core/util/image.h"
#include "core/weave/cloth_spec.h"

namespace clothbake {

/// Linear RGB, `block` pixels per crossing, a one-pixel dark line between
/// blocks when block >= 4 so single threads stay countable.
Image drawdown_image(const ClothSpec& spec, int block);

/// The repeat's size in threads (ends, picks): the draft's, or the least
/// common multiple with the colour and size sequences.
void repeat_threads(const ClothSpec& spec, int& ends, int& picks);

}  // namespace clothbake
