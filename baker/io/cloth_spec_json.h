#pragma once
/// Reads a ClothSpec from JSON (format: docs/cloth-spec.md).

#include <string>

#include "core/cloth_spec.h"
#include "io/json_reader.h"

namespace clothbake::io {

/// Fills a ClothSpec from a JSON object (absent keys keep their defaults),
/// refusing unknown keys and wrong types, then validates it. Errors name the
/// file and the full field path.
ClothSpec cloth_spec_from_json(const JsonObject& spec_json);

/// Loads a cloth spec file, or a scene file (a JSON object with "objects"),
/// in which case the first object's "cloth" is used: inline, or a path
/// relative to the scene file.
ClothSpec load_cloth_spec(const std::string& spec_or_scene_path);

}  // namespace clothbake::io
