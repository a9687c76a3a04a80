#include "io/material_merge.h"

#include <algorithm>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/material_bake/material_shard.h"
#include "core/material_bake/parallax_fit.h"
#include "core/util/error.h"
#include "io/folder_output.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct PartManifest {
  std::string dir, path;
  json doc;
  int part = 0, of = 0;
};

/// The manifest without what differs from part to part by design: the
/// shard, and what each part knows only of its own view nodes.
json shared_fields(json doc) {
  for (const char* key : {"shard", "ranks", "errors", "max_rank", "bake"}) doc.erase(key);
  return doc;
}

/// "/optics/step_cells" -> "optics.step_cells", "/a/b/0" -> "a.b[0]".
std::string field_of_pointer(const std::string& pointer) {
  std::string field;
  size_t i = 1;
  while (i <= pointer.size()) {
    const size_t end = std::min(pointer.find('/', i), pointer.size());
    const std::string token = pointer.substr(i, end - i);
    const bool index = !token.empty() && std::all_of(token.begin(), token.end(), ::isdigit);
    field += index ? "[" + token + "]" : (field.empty() ? "" : ".") + token;
    i = end + 1;
  }
  return field;
}

std::string value_at(const json& doc, const std::string& pointer) {
  const json::json_pointer p(pointer);
  return doc.contains(p) ? doc.at(p).dump() : "nothing";
}

PartManifest read_part_manifest(const std::string& dir) {
  PartManifest m;
  m.dir = dir;
  m.path = (fs::path(dir) / k_folder_manifest_name).string();
  m.doc = parse_json_text(read_text_file(m.path, "a JSON file"), m.path);
  if (!m.doc.is_object() || m.doc.value("format", "") != k_material_format_name)
    throw InputError("format", "is not a material folder's manifest", m.path);
  if (!m.doc.contains("shard") || !m.doc["shard"].is_object())
    throw InputError("shard",
                     "is missing: " + dir +
                         " is a whole material, not a part of a sharded bake "
                         "(clothbake material --shard I/N)",
                     m.path);
  const json& s = m.doc["shard"];
  if (!s.contains("part") || !s["part"].is_number_integer())
    throw InputError("shard.part", "must be an integer", m.path);
  if (!s.contains("of") || !s["of"].is_number_integer())
    throw InputError("shard.of", "must be an integer", m.path);
  m.part = s["part"].get<int>();
  m.of = s["of"].get<int>();
  return m;
}

/// Every manifest against the first, then the parts' numbers: one of each.
void check_parts_belong(const std::vector<PartManifest>& parts) {
  const PartManifest& first = parts.front();
  const json shared = shared_fields(first.doc);
  for (const PartManifest& p : parts) {
    const json patch = json::diff(shared, shared_fields(p.doc));
    if (!patch.empty()) {
      const std::string pointer = patch.front().at("path").get<std::string>();
      throw InputError(field_of_pointer(pointer),
                       "differs between the parts: " + first.dir + " has " +
                           value_at(first.doc, pointer) + ", " + p.dir + " has " +
                           value_at(p.doc, pointer) + " (parts of one bake share every setting)",
                       p.path);
    }
    if (p.part < 1 || p.part > p.of)
      throw InputError(
          "shard.part",
          "must be in [1, " + std::to_string(p.of) + "], got " + std::to_string(p.part), p.path);
    if (p.of != first.of)
      throw InputError("shard.of",
                       "is " + std::to_string(p.of) + " here but " + std::to_string(first.of) +
                           " in " + first.dir + " (parts of one bake have one count)",
                       p.path);
  }
  if (int(parts.size()) != first.of) {
    std::vector<int> given;
    for (const PartManifest& p : parts) given.push_back(p.part);
    std::sort(given.begin(), given.end());
    std::string missing;
    for (int i = 1; i <= first.of; ++i)
      if (!std::binary_search(given.begin(), given.end(), i))
        missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    if (!missing.empty() && int(parts.size()) < first.of)
      throw InputError("shard.part",
                       "part(s) " + missing + " of " + std::to_string(first.of) +
                           " missing: " + std::to_string(parts.size()) + " given",
                       first.path);
  }
  for (size_t a = 0; a < parts.size(); ++a)
    for (size_t b = a + 1; b < parts.size(); ++b)
      if (parts[a].part == parts[b].part)
        throw InputError("shard.part",
                         parts[a].dir + " and " + parts[b].dir + " are both part " +
                             std::to_string(parts[a].part) + " of " + std::to_string(first.of),
                         parts[b].path);
}

}  // namespace

ClothMaterial merge_material_parts(const std::vector<std::string>& dirs, MaterialInfo& info,
                                   uint64_t memory_budget) {
  if (dirs.empty()) throw InputError("", "no material parts to merge");
  std::vector<PartManifest> parts;
  for (const std::string& dir : dirs) parts.push_back(read_part_manifest(dir));
  check_parts_belong(parts);
  int max_rank = 0;
  for (const PartManifest& p : parts) max_rank = std::max(max_rank, p.doc.value("max_rank", 0));

  ClothMaterial whole;
  info.stats = {};
  for (size_t i = 0; i < parts.size(); ++i) {
    MaterialInfo part_info;
    const ClothMaterial part =
        read_material(parts[i].dir, part_info, memory_budget, SharedParts::Accept);
    if (i == 0) {
      whole = part;
      whole.max_rank = max_rank;
      if (whole.layout().table_bytes(max_rank) > memory_budget)
        throw InputError("max_rank",
                         "the merged table needs " +
                             std::to_string(whole.layout().table_bytes(max_rank) >> 20) +
                             " MiB, over the memory budget",
                         parts[i].path);
      whole.allocate();
      whole.shard = {};
      info.cloth_name = part_info.cloth_name;
      info.source = part_info.source;
    }
    copy_material_views(part, material_shard_views(part.view_grid, part.shard), whole);
    info.stats.rays += part_info.stats.rays;
    info.stats.march_samples += part_info.stats.march_samples;
    info.stats.fiber_evaluations += part_info.stats.fiber_evaluations;
  }
  if (whole.settings.view_parallax) whole.parallax_depth_mm = fit_view_parallax(whole).depth_mm;
  return whole;
}

}  // namespace clothbake::io
