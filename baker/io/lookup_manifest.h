#pragma once
/// A lookup folder's manifest.json, both directions (docs/formats/lookup.md):
/// what the folder holds, each object's layout and flags, and what the bake
/// recorded. The images are lookup_io's; this file only names them.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/bake/bake_settings.h"
#include "core/bake/lookup_table.h"
#include "core/geometry/mesh_summary.h"
#include "core/scene/scene.h"

namespace clothbake::io {

inline constexpr int k_lookup_format_version = 2;
inline constexpr const char* k_lookup_manifest_name = "manifest.json";

/// What the manifest records besides the tables themselves.
struct LookupInfo {
  std::string scene_path;                 ///< as given on the command line
  std::string scene_hash;                 ///< hash of the scene as loaded (scene_fingerprint)
  std::vector<std::string> cloth_hashes;  ///< per object: VolumeTexture::content_hash, hex
  std::vector<int> quad_counts;           ///< per object
  /// Per object: the mesh it was baked from, summarised (absent in lookups
  /// written before it was recorded).
  std::vector<std::optional<MeshSummary>> meshes;
  BakeSettings settings;
  nlohmann::json statistics;  ///< free-form: seconds, savings, ...
};

/// The image file of object `object`'s side (0 front, 1 back).
std::string lookup_image_name(size_t object, int side);

/// True if the side's atlas holds any square (it then has an image file).
bool side_has_atlas(const LookupTable& t, int side);

/// The manifest of `tables` (atlases sized; their pixels are not read).
nlohmann::json lookup_manifest_json(const std::vector<LookupTable>& tables, const LookupInfo& info,
                                    const Scene& scene);

/// A parsed manifest: the tables with their layout and flags, atlases sized
/// but without pixels, and per object and side the image file that holds
/// them ("" for a side without an atlas) and the manifest field naming it.
struct LookupManifest {
  LookupInfo info;
  std::vector<LookupTable> tables;
  std::vector<std::array<std::string, 2>> image_files, image_fields;
};

/// Parses and checks a manifest's text (`manifest_path` names it in errors).
/// With `expected_scene_hash` not empty, refuses a lookup of another scene.
/// Errors name the file and the field (InputError).
LookupManifest parse_lookup_manifest(const std::string& manifest_text,
                                     const std::string& manifest_path,
                                     const std::string& expected_scene_hash = {});

/// What a manifest records of its scene: the lights and the object names
/// (nothing else is filled). Lets merge rewrite a manifest without the scene
/// file.
Scene parse_lookup_scene(const std::string& manifest_text, const std::string& manifest_path);

}  // namespace clothbake::io
