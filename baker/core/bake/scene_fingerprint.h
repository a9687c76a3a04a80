#pragma once
/// What identifies a scene to a lookup: a hash of everything in a scene that
/// changes what a bake computes (meshes, cloth specs, lights, the render
/// settings that change a march; not the camera, not spp). A lookup is only
/// valid for a scene with the same fingerprint (docs/formats/lookup.md,
/// `scene_hash`).

#include <string>

#include "core/scene/scene.h"

namespace clothbake {

/// The fingerprint as 16 lowercase hex digits. Floats enter by their bits,
/// so it is exact and the same on every platform with IEEE floats.
std::string scene_fingerprint(const Scene& scene);

}  // namespace clothbake
