#pragma once
/// Reading and writing a baked lookup folder (format: docs/lookup-format.md):
/// `manifest.json` plus, per cloth object and side (front/back), one
/// half-float RGBA OpenEXR atlas packing the squares of the (quad, direction
/// node) pairs the bake computed.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/baker.h"
#include "core/lookup_table.h"
#include "core/mesh_summary.h"
#include "core/scene.h"

namespace clothbake::io {

inline constexpr int k_lookup_format_version = 2;

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

/// A hash of everything in a scene that changes what a bake computes
/// (meshes, cloth specs, lights, render settings except spp; not the camera),
/// as 16 hex digits. A lookup is only valid for a scene with the same hash.
std::string scene_fingerprint(const Scene& scene);

/// Refuses, before any work, a destination `write_lookup` would refuse: a
/// file, or a non-empty folder that is not a lookup (it would be replaced).
void check_lookup_destination(const std::string& dir);

/// Writes the lookup folder atomically: everything goes into a temporary
/// sibling folder which replaces `dir` only when complete (an existing `dir`
/// is kept until then). Throws InputError on failure, leaving `dir` as it was.
void write_lookup(const std::string& dir, const std::vector<LookupTable>& tables,
                  const LookupInfo& info, const Scene& scene);

/// Reads a lookup folder. Checks the format version, that every file the
/// manifest names exists with the right size and channels, and (when
/// `expected_scene_hash` is not empty) that it was baked for that scene.
/// Errors name the file and the field (InputError).
std::vector<LookupTable> read_lookup(const std::string& dir, LookupInfo& info,
                                     const std::string& expected_scene_hash = {});

/// read_lookup with the manifest given as text (the content of
/// DIR/manifest.json); the images it names are read from `dir`.
std::vector<LookupTable> read_lookup_manifest(const std::string& manifest_text,
                                              const std::string& dir, LookupInfo& info,
                                              const std::string& expected_scene_hash = {});

/// What a lookup folder records of its scene: the lights and the object
/// names (nothing else is filled). Lets merge rewrite a manifest without the
/// scene file.
Scene read_lookup_scene(const std::string& dir);

/// read_lookup_scene with the manifest given as text (DIR/manifest.json's content).
Scene read_lookup_scene_manifest(const std::string& manifest_text, const std::string& dir);

/// Joins partial bakes of one scene (same layout, disjoint or overlapping
/// quads) into one lookup, identical to a whole bake of the union.
/// Throws InputError naming the folder that does not match the first.
std::vector<LookupTable> merge_lookups(const std::vector<std::string>& dirs, LookupInfo& info);

/// Estimated bytes of the lookup files, uncompressed (for refusals and reports).
uint64_t lookup_bytes(const std::vector<LookupTable>& tables);

}  // namespace clothbake::io
