#include "io/material_manifest.h"

#include <vector>

#include "core/material/yarn_colours.h"
#include "core/material_bake/material_shard.h"
#include "core/util/hex.h"
#include "io/cloth_spec_json.h"
#include "io/enum_names.h"

namespace clothbake::io {

namespace {
using Imath::V3f;
using nlohmann::json;

json v3_json(const V3f& c) { return json::array({c.x, c.y, c.z}); }

json palette_json(const YarnPalette& p) {
  auto family = [](const V3f& color, const std::vector<V3f>& colors) {
    json f = {{"color", v3_json(color)}};
    for (const V3f& c : colors) f["colors"].push_back(v3_json(c));  // absent when none
    return f;
  };
  return {{"warp", family(p.warp_color, p.warp_colors)},
          {"weft", family(p.weft_color, p.weft_colors)}};
}

/// "cloth": its name, hash and source, and for colour-free parts the cloth
/// itself, its colours, written repeats and threads.
json cloth_json(const ClothMaterial& m, const MaterialInfo& info) {
  json c = {{"name", info.cloth_name}, {"hash", hex16(m.cloth_hash)}, {"source", info.source}};
  if (m.colour_parts()) {
    c["spec"] = cloth_spec_json(m.cloth);
    c["colors"] = palette_json(m.palette);
    c["written_repeats"] = {m.written_repeats.x, m.written_repeats.y};
    c["threads"] = {{"warp", {{"centres_mm", thread_centres_mm(m.cloth, true)}}},
                    {"weft", {{"centres_mm", thread_centres_mm(m.cloth, false)}}}};
  }
  return c;
}

/// "crossings" of a material addressed per crossing.
json crossings_json(const ClothMaterial& m) {
  const MaterialSettings& s = m.settings;
  json c = {{"ends", m.crossings.ends},
            {"picks", m.crossings.picks},
            {"blocks", m.crossings.count()},
            {"context", s.context},
            {"members", s.members},
            {"stencil", enum_name(k_crossing_stencil_names, s.stencil)},
            {"file", k_material_crossings_file}};
  // Written only when used: a material without phase bins keeps its bytes.
  if (s.phase_bins > 1) c["phase_bins"] = s.phase_bins;
  return c;
}

json optics_json(const MaterialOptics& o) {
  json j = {
      {"depth_scale", o.depth_scale},
      {"extinction_per_mm", o.extinction_per_mm},
      {"shading", enum_name(k_shading_names, o.shading)},
      {"isotropic_albedo", {o.isotropic_albedo.x, o.isotropic_albedo.y, o.isotropic_albedo.z}},
      {"fiber_model", enum_name(k_fiber_model_names, o.fiber_model)},
      {"fiber_samples", o.fiber_samples},
      {"fiber_seed", o.fiber_seed},
      {"step_cells", o.step_cells},
      {"cutoff", o.cutoff},
      {"light_roulette", o.light_roulette}};
  // Written where the map stretches the repeat, so that an unstretched
  // material's manifest keeps its bytes.
  if (o.aspect != 1.0f) j["aspect"] = o.aspect;
  return j;
}

/// The settings a bake was asked, each at the manifest's top level.
void add_settings(const MaterialSettings& s, json& j) {
  j["texels"] = s.texels;
  j["directions"] = s.directions;
  j["light_directions"] = s.light_directions;
  j["direction_map"] = "hemi-octahedral";
  j["light_direction_map"] = enum_name(k_light_map_names, s.light_map);
  j["spp"] = s.spp;
  j["max_error"] = s.max_error;
  j["field_supersample"] = s.field_supersample;
  // Written where it is not the method every material before it used, so
  // that an interpolated material's manifest keeps its bytes.
  if (s.light_fields == LightFieldMethod::LayerMarch)
    j["light_fields"] = enum_name(k_light_field_names, s.light_fields);
  j["fiber_tangent_nodes"] = s.fiber_tangent_nodes;
  j["view_parallax"] = s.view_parallax;
  j["seed"] = s.seed;
}

/// The table's ranks and errors per view node, and its files.
void add_table(const ClothMaterial& m, json& j) {
  j["max_rank"] = m.max_rank;
  json ranks = json::array(), errors = json::array();
  for (int v = 0; v < m.view_count(); ++v) {
    ranks.push_back(m.rank[v]);
    errors.push_back(m.error[v]);
  }
  j["ranks"] = ranks;
  j["errors"] = errors;
  json levels = json::array();
  for (int l = 0; l < m.levels(); ++l) levels.push_back(material_level_file(l));
  j["files"] = {{"levels", levels}, {"light_factors", k_material_light_file}};
}
}  // namespace

json material_manifest_json(const ClothMaterial& m, const MaterialInfo& info) {
  const MaterialSettings& s = m.settings;
  json j;
  j["format"] = k_material_format_name;
  // Version 3 only where its layout differs: a version-2 reader still reads
  // every material addressed over the whole repeat.
  j["version"] = m.addressed() ? k_material_format_version : 2;
  j["parts"] = enum_name(k_material_parts_names, s.parts);
  j["cloth"] = cloth_json(m, info);
  j["repeat_mm"] = {m.repeat_mm.x, m.repeat_mm.y, m.repeat_mm.z};
  j["levels"] = m.levels();
  if (m.addressed()) {
    j["address"] = enum_name(k_material_address_names, s.address);
    j["crossings"] = crossings_json(m);
  }
  add_settings(s, j);
  j["parallax_depth_mm"] = m.parallax_depth_mm;
  j["optics"] = optics_json(m.optics);
  add_table(m, j);
  if (!m.shard.whole())
    j["shard"] = {{"part", m.shard.index + 1},
                  {"of", m.shard.count},
                  {"views", material_shard_views(m.view_grid, m.shard)}};
  j["bake"] = {{"rays", info.stats.rays},
               {"march_samples", info.stats.march_samples},
               {"fiber_evaluations", info.stats.fiber_evaluations}};
  return j;
}

}  // namespace clothbake::io
