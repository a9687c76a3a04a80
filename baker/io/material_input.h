#pragma once
/// What `clothbake material` bakes from, read from a file: a scene's object
/// (the scene kept alive for its volume) or a cloth spec, made into a
/// MaterialSource (core/material_bake/material_source.h), with the threads
/// its repeat spans for the texel advice (bake_rules.h).

#include <cstdint>
#include <memory>
#include <string>

#include "core/material_bake/material_source.h"
#include "core/scene/cloth_scene.h"

namespace clothbake::io {

struct MaterialInput {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<ClothScene> prepared;  ///< refers to `scene`
  MaterialSource source;                 ///< may refer to `prepared`
  std::string cloth_name;                ///< the scene object's name, or the spec file's stem
  /// Warp ends and weft picks over the material's repeat (0: a VDB volume,
  /// whose threads are not known).
  int ends = 0, picks = 0;
};

/// What is asked of the parts: colour-free where possible (Auto), or
/// exactly RGB or colour-free (an InputError on "parts" when colour-free
/// parts are not possible for the object).
enum class PartsRequest { Auto, Rgb, ColourFree };

/// Reads `path`, a scene (its object named or indexed by `object`, the first
/// when empty; InputError on "object" when there is none such) or a cloth
/// spec. Errors carry the file.
MaterialInput read_material_input(const std::string& path, const std::string& object,
                                  PartsRequest parts, uint64_t memory_budget_bytes);

}  // namespace clothbake::io
