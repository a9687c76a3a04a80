#pragma once
/// A baked lookup folder on disk (format: docs/formats/lookup.md):
/// `manifest.json` (io/lookup_manifest.h) plus, per cloth object and side
/// (front/back), one half-float RGBA OpenEXR atlas packing the squares of the
/// (quad, direction node) pairs the bake computed. Written as a whole or not
/// at all (io/atomic_file.h, publish_folder); merged from partial bakes.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/bake/lookup_table.h"
#include "core/bake/scene_fingerprint.h"
#include "core/scene/scene.h"
#include "io/lookup_manifest.h"

namespace clothbake::io {

/// The scene fingerprint is core logic (core/bake/scene_fingerprint.h); the
/// commands call it from here as they always have.
using ::clothbake::scene_fingerprint;

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
