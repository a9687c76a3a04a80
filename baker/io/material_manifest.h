#pragma once
/// A material folder's manifest.json as written (docs/formats/material.md),
/// and the names of the folder's files, which the writer and the reader
/// (material_io.h) both use.

#include <string>

#include <nlohmann/json.hpp>

#include "core/material/cloth_material.h"
#include "io/material_io.h"

namespace clothbake::io {

inline constexpr const char* k_material_light_file = "light_factors.exr";
inline constexpr const char* k_material_crossings_file = "crossings.exr";
/// "level_<m>.exr": mip level m's coefficient atlas.
inline std::string material_level_file(int m) { return "level_" + std::to_string(m) + ".exr"; }

/// The manifest of `material`: its format and version, cloth, settings,
/// optics, ranks and errors, files, shard and the bake's counts.
nlohmann::json material_manifest_json(const ClothMaterial& material, const MaterialInfo& info);

}  // namespace clothbake::io
