#pragma once
/// Reads a ClothSpec from JSON (format: docs/formats/cloth-spec.md).

#include <string>

#include "core/weave/cloth_spec.h"
#include "io/json_reader.h"

namespace clothbake::io {

/// Fills a ClothSpec from a JSON object (absent keys keep their defaults),
/// refusing unknown keys and wrong types, then validates it. Errors name the
/// file and the full field path.
ClothSpec cloth_spec_from_json(const JsonObject& spec_json);

/// The spec as JSON in the same format, every field written (the draft
/// explicit when it has one): cloth_spec_from_json reads it back equal.
nlohmann::json cloth_spec_json(const ClothSpec& spec);

/// A WIF file's cloth with clothbake's defaults for what the file does not
/// say (io/wif_reader.h), validated; errors name the WIF file.
struct WifFile;
ClothSpec cloth_spec_from_wif(const WifFile& wif);

/// Reads a cloth spec, or a WIF file (by its extension), or a scene (a JSON object with "objects"), in which
/// case the first object's "cloth" is used: inline, or the path of a cloth
/// spec file (not another scene) relative to `path`. `text` is the content of
/// `path`, which errors name.
ClothSpec cloth_spec_from_text(const std::string& text, const std::string& spec_or_scene_path);

/// cloth_spec_from_text of the file's content.
ClothSpec load_cloth_spec(const std::string& spec_or_scene_path);

/// Loads a file that must be a cloth spec (a scene's "cloth" by path): a
/// scene there is refused, so scenes cannot name each other in a loop.
ClothSpec load_cloth_spec_file(const std::string& spec_path);

}  // namespace clothbake::io
