#include "io/lookup_io.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include "core/bake/lookup_merge.h"
#include "core/util/error.h"
#include "io/atomic_file.h"
#include "io/data_image.h"
#include "io/folder_output.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

/// Checks the table's shape before anything is written about it.
void check_table(const LookupTable& t, size_t object, int k) {
  const std::string field = "objects[" + std::to_string(object) + "]";
  if (t.dirs.k != k)
    throw InputError(field, "all objects of one lookup must share K (" + std::to_string(k) +
                                "), this one has " + std::to_string(t.dirs.k));
  if (t.baked.size() != t.sizes.size() * size_t(t.node_count()) || t.slots.size() != t.baked.size())
    throw InputError(field, "baked flags or squares do not match quads x nodes");
  for (int side = 0; side < 2; ++side)
    if (side_has_atlas(t, side) &&
        t.atlases[side].pixels.size() !=
            size_t(t.atlases[side].width) * size_t(t.atlases[side].height) * 4)
      throw InputError(field, "the atlas of side " + std::to_string(side) + " is not allocated");
}

/// The atlas of one side, as it is in memory.
void write_side_image(const std::string& path, const LookupTable& t, int side) {
  const LookupAtlas& atlas = t.atlases[side];
  write_data_image(path, atlas.width, atlas.height, {"R", "G", "B", "A"}, atlas.pixels.data(), 3);
}

/// Reads a side atlas of want_w x want_h RGBA pixels, as halves.
std::vector<Imath::half> read_side_image(const std::string& path, const std::string& named_by,
                                         int64_t want_w, int64_t want_h) {
  DataImageExpect want;
  want.width = int(want_w);
  want.height = int(want_h);
  want.channels = {"R", "G", "B", "A"};
  want.by_name = false;  // the file's first four channels, as written
  want.missing =
      "cannot read the lookup image: missing (named by " + named_by + " in manifest.json)";
  want.cannot_read = "cannot read the lookup image: ";
  want.corrupt = "corrupt or truncated file";
  want.size_from = "the manifest (" + named_by + ".size)";
  want.channels_from = "a lookup image has 4 (R, G, B, A)";
  return read_data_image_half(path, want);
}

}  // namespace

void check_lookup_destination(const std::string& dir) { check_folder_destination(dir, "lookup"); }

void write_lookup(const std::string& dir, const std::vector<LookupTable>& tables,
                  const LookupInfo& info, const Scene& scene) {
  // The tables' shapes are checked before anything is written.
  const int k = tables.empty() ? 0 : tables[0].dirs.k;
  for (size_t o = 0; o < tables.size(); ++o) check_table(tables[o], o, k);
  write_folder(dir, "lookup", 0, [&](const fs::path& temp_dir) {
    for (size_t o = 0; o < tables.size(); ++o)
      for (int side = 0; side < 2; ++side)
        if (side_has_atlas(tables[o], side))
          write_side_image((temp_dir / lookup_image_name(o, side)).string(), tables[o], side);
    write_json_file((temp_dir / k_lookup_manifest_name).string(),
                    lookup_manifest_json(tables, info, scene));
  });
}

std::vector<LookupTable> read_lookup_manifest(const std::string& manifest_text,
                                              const std::string& dir, LookupInfo& info,
                                              const std::string& expected_scene_hash) {
  const std::string manifest_path = (fs::path(dir) / k_lookup_manifest_name).string();
  LookupManifest m = parse_lookup_manifest(manifest_text, manifest_path, expected_scene_hash);
  for (size_t o = 0; o < m.tables.size(); ++o)
    for (int side = 0; side < 2; ++side) {
      if (m.image_files[o][side].empty()) continue;
      LookupAtlas& atlas = m.tables[o].atlases[side];
      atlas.pixels = read_side_image((fs::path(dir) / m.image_files[o][side]).string(),
                                     m.image_fields[o][side], atlas.width, atlas.height);
    }
  info = std::move(m.info);
  return std::move(m.tables);
}

std::vector<LookupTable> read_lookup(const std::string& dir, LookupInfo& info,
                                     const std::string& expected_scene_hash) {
  const std::string manifest_path = (fs::path(dir) / k_lookup_manifest_name).string();
  return read_lookup_manifest(read_text_file(manifest_path, "a JSON file"), dir, info,
                              expected_scene_hash);
}

Scene read_lookup_scene_manifest(const std::string& manifest_text, const std::string& dir) {
  return parse_lookup_scene(manifest_text, (fs::path(dir) / k_lookup_manifest_name).string());
}

Scene read_lookup_scene(const std::string& dir) {
  const std::string manifest_path = (fs::path(dir) / k_lookup_manifest_name).string();
  return read_lookup_scene_manifest(read_text_file(manifest_path, "a JSON file"), dir);
}

std::vector<LookupTable> merge_lookups(const std::vector<std::string>& dirs, LookupInfo& info) {
  if (dirs.empty()) throw InputError("", "no lookup folders to merge");
  LookupInfo first_info;
  std::vector<std::vector<LookupTable>> parts;
  parts.push_back(read_lookup(dirs[0], first_info));
  std::vector<LookupTable> merged = parts[0];
  for (LookupTable& t : merged)
    for (LookupAtlas& a : t.atlases) a.pixels.clear();  // rebuilt below from every part
  json part_statistics = json::array({first_info.statistics});
  int quad_begin = first_info.settings.quad_begin, quad_end = first_info.settings.quad_end;

  // Step 1: every part must be a slice of the same bake.
  for (size_t p = 1; p < dirs.size(); ++p) {
    LookupInfo part_info;
    std::vector<LookupTable> part = read_lookup(dirs[p], part_info);
    auto differs = [&](const std::string& what, const std::string& detail = {}) {
      throw InputError("",
                       what + " differs from " +
                           (fs::path(dirs[0]) / k_lookup_manifest_name).string() + detail +
                           "; parts to merge must come from one scene and one bake",
                       (fs::path(dirs[p]) / k_lookup_manifest_name).string());
    };
    if (part_info.scene_hash != first_info.scene_hash)
      differs("scene_hash",
              " (" + part_info.scene_hash + " here, " + first_info.scene_hash + " there)");
    if (part.size() != merged.size()) differs("the number of objects");
    if (!part.empty() && part[0].dirs.k != merged[0].dirs.k) differs("direction_map.k");
    if (!part.empty() && part[0].dirs.map != merged[0].dirs.map) differs("direction_map.type");
    // Texels of another spp or seed would not be those of a whole bake.
    const BakeSettings &a = first_info.settings, &b = part_info.settings;
    if (a.spp != b.spp) differs("settings.spp");
    if (a.seed != b.seed) differs("settings.seed");
    for (size_t o = 0; o < part.size(); ++o) {
      const std::string what = layout_mismatch(merged[o], part[o]);
      if (!what.empty()) differs("objects[" + std::to_string(o) + "]." + what);
      if (part_info.cloth_hashes[o] != first_info.cloth_hashes[o])
        differs("objects[" + std::to_string(o) + "].cloth_hash");
    }
    quad_begin = std::min(quad_begin, b.quad_begin);
    quad_end = (quad_end < 0 || b.quad_end < 0) ? -1 : std::max(quad_end, b.quad_end);
    part_statistics.push_back(part_info.statistics);
    parts.push_back(std::move(part));
  }

  // Step 2: the tables themselves (core: the union of flags and squares).
  merge_tables(merged, parts);

  // A union reaching the last quad of every object reads as "to the last" (-1),
  // as in a whole bake.
  int most_quads = 0;
  for (const LookupTable& t : merged) most_quads = std::max(most_quads, t.quad_count());
  info = first_info;
  info.settings.quad_begin = quad_begin;
  info.settings.quad_end = quad_end >= most_quads ? -1 : quad_end;
  info.statistics = {{"merged_from", dirs}, {"parts", part_statistics}};
  return merged;
}

uint64_t lookup_bytes(const std::vector<LookupTable>& tables) {
  uint64_t bytes = 0;
  for (const LookupTable& t : tables) bytes += t.atlas_bytes();
  return bytes;
}

}  // namespace clothbake::io
