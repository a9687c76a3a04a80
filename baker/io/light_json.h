#pragma once
/// The one codec of a light in JSON, for the scene reader (docs/formats/scene.md,
/// "lights") and the lookup manifest (docs/formats/lookup.md, "lights").

#include <nlohmann/json.hpp>

#include "core/scene/light.h"
#include "io/json_reader.h"

namespace clothbake::io {

/// How a directional light's direction is spelled. A scene gives the way
/// the light travels (`direction`, any length, normalised on reading); a
/// lookup manifest stores the unit vector toward the light (`to_light`) as
/// computed, so that a merge writes it back bit for bit.
enum class LightSpelling { Scene, Stored };

/// Reads a light; errors name the field (InputError through `j`).
Light read_light(const JsonObject& j, LightSpelling spelling);

/// A light as the manifest stores it (LightSpelling::Stored).
nlohmann::json stored_light_json(const Light& light);

}  // namespace clothbake::io
