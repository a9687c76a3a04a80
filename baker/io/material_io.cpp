#include "io/material_io.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/material_bake/bake_rules.h"
#include "core/material_bake/material_bake.h"
#include "core/material_bake/material_shard.h"
#include "core/util/error.h"
#include "core/util/hex.h"
#include "io/cloth_spec_json.h"
#include "io/data_image.h"
#include "io/enum_names.h"
#include "io/folder_output.h"
#include "io/json_reader.h"
#include "io/material_manifest.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {
namespace fs = std::filesystem;
using Imath::V3f;
using nlohmann::json;

constexpr const char* k_light_file = k_material_light_file;
constexpr const char* k_crossings_file = k_material_crossings_file;
std::string level_file(int m) { return material_level_file(m); }

/// "k0003": zero-padded, so that the names sort in component order (OpenEXR
/// stores channels sorted by name; readers find them by name).
std::string component_name(int k) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "k%04d", k);
  return buf;
}

/// The coefficient channels' names: alpha, then each component's R, G, B,
/// or its colour-free parts.
std::vector<std::string> level_channels(int max_rank, MaterialParts parts) {
  std::vector<std::string> names{"A"};
  const std::vector<const char*> rgb{"R", "G", "B"};
  const std::vector<const char*> free{"specular", "warp", "weft", "warp_next", "weft_next"};
  for (int k = 0; k < max_rank; ++k)
    for (const char* c : parts == MaterialParts::Rgb ? rgb : free)
      names.push_back(component_name(k) + "." + c);
  return names;
}

/// The light factors' channels: one per component, at least one.
std::vector<std::string> light_channels(int max_rank) {
  std::vector<std::string> names;
  for (int k = 0; k < std::max(1, max_rank); ++k) names.push_back(component_name(k));
  return names;
}

/// What the reader expects of a material image, and how its errors read.
DataImageExpect expect(int width, int height, std::vector<std::string> channels) {
  DataImageExpect want;
  want.width = width;
  want.height = height;
  want.channels = std::move(channels);
  want.finite = true;
  want.missing = "missing: the material folder is incomplete";
  want.channels_from = "the manifest's max_rank gives " + std::to_string(want.channels.size());
  return want;
}

/// Level `l`'s coefficient atlas, as written: alpha, then RGB per component.
std::vector<Imath::half> level_pixels(const ClothMaterial& m, int l) {
  const MaterialLayout layout = m.layout();
  const size_t ch = size_t(layout.channels);
  const size_t nc = 1 + ch * size_t(m.max_rank);
  const int side = layout.level_side(l);
  const size_t texels = layout.level_texels(l);
  std::vector<Imath::half> pixels(size_t(layout.atlas_width(l)) * layout.atlas_height(l) * nc);
  for (int v = 0; v < m.view_count(); ++v)
    for (int y = 0; y < layout.level_rows(l); ++y)
      for (int x = 0; x < side; ++x) {
        const size_t t = size_t(y) * side + x;
        Imath::half* out = &pixels[layout.atlas_pixel(v, x, y, l) * nc];
        out[0] = m.alpha[l][size_t(v) * texels + t];
        const V3f* c = &m.coefficients[l][(size_t(v) * texels + t) * m.max_rank];
        for (int k = 0; k < m.max_rank; ++k)
          out[1 + ch * k] = c[k].x, out[2 + ch * k] = c[k].y, out[3 + ch * k] = c[k].z;
        if (ch == 5) {
          const Imath::V2f* e = &m.coefficients_next[l][(size_t(v) * texels + t) * m.max_rank];
          for (int k = 0; k < m.max_rank; ++k) out[4 + ch * k] = e[k].x, out[5 + ch * k] = e[k].y;
        }
      }
  return pixels;
}

/// The light factors' image: a row per view node, a pixel per light node.
std::vector<float> light_pixels(const ClothMaterial& m) {
  const size_t nc = light_channels(m.max_rank).size(), L = size_t(m.light_count());
  std::vector<float> pixels(L * m.view_count() * nc, 0.0f);
  for (int v = 0; v < m.view_count(); ++v)
    for (size_t n = 0; n < L; ++n)
      for (int k = 0; k < m.max_rank; ++k)
        pixels[(size_t(v) * L + n) * nc + k] =
            m.light_factors[(size_t(v) * L + n) * m.max_rank + k];
  return pixels;
}

/// Format and version, checked first: a manifest of another kind or version
/// is refused before any of its fields is read.
void check_format(const JsonObject& top) {
  for (const char* key : {"format", "version", "cloth", "repeat_mm", "texels", "levels",
                          "directions", "light_directions", "spp", "max_error", "seed", "optics",
                          "max_rank", "ranks", "errors", "files"})
    if (!top.has(key)) top.fail(key, "is missing");
  std::string format;
  top.read("format", format);
  if (format != k_material_format_name)
    top.fail("format",
             "expected \"" + std::string(k_material_format_name) + "\", got \"" + format + "\"");
  int version = 0;
  top.read("version", version);
  if (version < 1 || version > k_material_format_version)
    top.fail("version", "this material has format version " + std::to_string(version) +
                            "; this clothbake reads versions 1 to " +
                            std::to_string(k_material_format_version));
}

MaterialSettings read_settings(const JsonObject& top, const std::string& manifest_path) {
  MaterialSettings s;
  top.read("texels", s.texels);
  top.read("directions", s.directions);
  top.read("light_directions", s.light_directions);
  top.read("spp", s.spp);
  top.read("max_error", s.max_error);
  top.read("seed", s.seed);
  top.read("field_supersample", s.field_supersample);
  s.light_fields = LightFieldMethod::Interpolated;  // absent: how every older material was baked
  read_enum(top, "light_fields", k_light_field_names, s.light_fields);
  s.light_map = DirectionMap::HemiOctahedral;  // manifests older than the horizon map
  read_enum(top, "light_direction_map", k_light_map_names, s.light_map);
  top.read("fiber_tangent_nodes", s.fiber_tangent_nodes);
  s.view_parallax = false;  // manifests before it
  if (top.has("view_parallax")) {
    const nlohmann::json& vp = top.raw("view_parallax");
    if (!vp.is_boolean()) top.fail("view_parallax", "must be true or false");
    s.view_parallax = vp.get<bool>();
  }
  s.parts = MaterialParts::Rgb;  // version 1
  read_enum(top, "parts", k_material_parts_names, s.parts);
  s.address = MaterialAddress::Repeat;  // versions 1 and 2
  read_enum(top, "address", k_material_address_names, s.address);
  if (s.address == MaterialAddress::Crossings) {
    if (s.parts != MaterialParts::SpecularWarpWeft)
      top.fail("address",
               "\"crossings\" needs colour-free parts (\"parts\": "
               "\"specular-warp-weft\")");
    if (!top.has("crossings"))
      top.fail("crossings", "is missing (the material is addressed per crossing)");
    top.object("crossings").read("context", s.context);
    top.object("crossings").read("members", s.members);
    s.stencil = CrossingStencil::Plus1;  // before the 3 x 3 stencil
    read_enum(top.object("crossings"), "stencil", k_crossing_stencil_names, s.stencil);
    s.phase_bins = 1;  // before phase bins
    top.object("crossings").read("phase_bins", s.phase_bins);
  }
  try {
    check_material_settings(s);
  } catch (const InputError& e) {
    throw InputError(e.field(), e.message(), manifest_path);
  }
  return s;
}

MaterialOptics read_optics(const JsonObject& o) {
  MaterialOptics op;
  o.read("depth_scale", op.depth_scale);
  o.read("aspect", op.aspect);  // absent (a material from before it was kept): 1
  o.read("extinction_per_mm", op.extinction_per_mm);
  read_enum(o, "shading", k_shading_names, op.shading);
  read_enum(o, "fiber_model", k_fiber_model_names, op.fiber_model);
  o.read("isotropic_albedo", op.isotropic_albedo);
  o.read("fiber_samples", op.fiber_samples);
  o.read("fiber_seed", op.fiber_seed);
  o.read("step_cells", op.step_cells);
  o.read("cutoff", op.cutoff);
  o.read("light_roulette", op.light_roulette);
  if (!(op.depth_scale > 0.0f) || !std::isfinite(op.depth_scale))
    o.fail(o.field("depth_scale"), "must be positive");
  if (!(op.aspect > 0.0f) || !std::isfinite(op.aspect))
    o.fail(o.field("aspect"), "must be positive");
  if (!(op.extinction_per_mm > 0.0f) || !std::isfinite(op.extinction_per_mm))
    o.fail(o.field("extinction_per_mm"), "must be positive");
  return op;
}

/// max_rank (bounded by the light nodes and the memory budget, before
/// anything is allocated), levels, and each view node's rank and error.
void read_table_shape(const JsonObject& top, uint64_t memory_budget, ClothMaterial& m) {
  top.read("max_rank", m.max_rank);
  if (m.max_rank < 0 || m.max_rank > m.light_count())
    top.fail("max_rank", "must be in [0, " + std::to_string(m.light_count()) + "]");
  const uint64_t bytes = m.layout().table_bytes(m.max_rank);
  if (bytes > memory_budget)
    top.fail("max_rank", "the table needs " + std::to_string(bytes >> 20) +
                             " MiB in memory, over the budget of " +
                             std::to_string(memory_budget >> 20) + " MiB");
  int levels = 0;
  top.read("levels", levels);
  m.allocate();
  if (levels != m.levels())
    top.fail("levels", std::to_string(m.texels()) + " texels give " + std::to_string(m.levels()) +
                           " levels, not " + std::to_string(levels));
  const json& ranks = top.raw("ranks");
  const json& errors = top.raw("errors");
  if (!ranks.is_array() || int(ranks.size()) != m.view_count())
    top.fail("ranks", "must list " + std::to_string(m.view_count()) + " view nodes");
  if (!errors.is_array() || int(errors.size()) != m.view_count())
    top.fail("errors", "must list " + std::to_string(m.view_count()) + " view nodes");
  for (int v = 0; v < m.view_count(); ++v) {
    if (!ranks[v].is_number_integer() || ranks[v].get<int>() < 0 ||
        ranks[v].get<int>() > m.max_rank)
      top.fail("ranks[" + std::to_string(v) + "]", "must be an integer in [0, max_rank]");
    if (!errors[v].is_number()) top.fail("errors[" + std::to_string(v) + "]", "must be a number");
    m.rank[v] = ranks[v].get<int>();
    m.error[v] = errors[v].get<float>();
  }
}

/// A part of a sharded bake (material_shard.h): its number, count and view
/// nodes, which must be the ones that part bakes. Refused unless `parts`
/// accepts parts: only merge reads them.
void read_shard(const JsonObject& top, SharedParts parts, ClothMaterial& m) {
  if (!top.has("shard")) return;
  const JsonObject shard = top.object("shard");
  int part = 0, of = 0;
  shard.read("part", part);
  shard.read("of", of);
  m.shard = MaterialShard{part - 1, of};
  try {
    check_material_shard(m.shard, m.view_count());
  } catch (const InputError& e) {
    shard.fail(shard.field("part"), e.message());
  }
  if (m.shard.whole())
    shard.fail(shard.field("of"), "must be at least 2 (a part of a sharded bake)");
  if (!shard.has("views")) shard.fail(shard.field("views"), "is missing");
  const json& listed = shard.raw("views");
  std::vector<int> views;
  if (listed.is_array())
    for (const json& v : listed) views.push_back(v.is_number_integer() ? v.get<int>() : -1);
  if (views != material_shard_views(m.view_grid, m.shard))
    shard.fail(shard.field("views"), "are not the view nodes part " + std::to_string(part) +
                                         " of " + std::to_string(of) + " bakes");
  if (parts == SharedParts::Refuse)
    shard.fail(shard.field("part"),
               "this folder is part " + std::to_string(part) + " of " + std::to_string(of) +
                   " of a sharded bake (clothbake material --shard): join the parts with "
                   "'clothbake merge PART... -o DIR' first");
}

/// Addressed per crossing: the classes set_cloth found from the cloth spec,
/// checked against the manifest's counts and the stored index (a reader
/// that finds other classes than the writer must not read the blocks).
void read_crossings(const std::string& dir, const JsonObject& c, const ClothMaterial& m) {
  int ends = 0, picks = 0, blocks = 0;
  c.read("ends", ends);
  c.read("picks", picks);
  c.read("blocks", blocks);
  if (ends != m.crossings.ends || picks != m.crossings.picks)
    c.fail(c.field("ends"), "the cloth spec has " + std::to_string(m.crossings.ends) + " x " +
                                std::to_string(m.crossings.picks) + " crossings, not " +
                                std::to_string(ends) + " x " + std::to_string(picks));
  if (blocks != m.crossings.count())
    c.fail(c.field("blocks"), "the cloth spec's crossings fall in " +
                                  std::to_string(m.crossings.count()) + " classes, not " +
                                  std::to_string(blocks));
  const std::string path = (fs::path(dir) / k_crossings_file).string();
  const std::vector<float> index = read_data_image_float(path, expect(ends, picks, {"block"}));
  for (size_t i = 0; i < index.size(); ++i)
    if (index[i] != float(m.crossings.class_of[i]))
      throw InputError("block",
                       "crossing (end " + std::to_string(i % size_t(ends)) + ", pick " +
                           std::to_string(i / size_t(ends)) + ") holds block " +
                           std::to_string(index[i]) + "; the cloth spec gives " +
                           std::to_string(m.crossings.class_of[i]),
                       path);
}

/// The level atlases and the light factors, into the allocated table.
void read_images(const std::string& dir, ClothMaterial& m) {
  const MaterialLayout layout = m.layout();
  const std::vector<std::string> channels = level_channels(m.max_rank, m.settings.parts);
  const size_t nc = channels.size();
  for (int l = 0; l < m.levels(); ++l) {
    const int side = layout.level_side(l);
    const std::vector<Imath::half> pixels =
        read_data_image_half((fs::path(dir) / level_file(l)).string(),
                             expect(layout.atlas_width(l), layout.atlas_height(l), channels));
    const size_t texels = layout.level_texels(l);
    for (int v = 0; v < m.view_count(); ++v)
      for (int y = 0; y < layout.level_rows(l); ++y)
        for (int x = 0; x < side; ++x) {
          const size_t t = size_t(y) * side + x;
          const Imath::half* in = &pixels[layout.atlas_pixel(v, x, y, l) * nc];
          m.alpha[l][size_t(v) * texels + t] = in[0];
          V3f* c = &m.coefficients[l][(size_t(v) * texels + t) * m.max_rank];
          const size_t ch = size_t(layout.channels);
          for (int k = 0; k < m.max_rank; ++k)
            c[k] = V3f(in[1 + ch * k], in[2 + ch * k], in[3 + ch * k]);
          if (ch == 5) {
            Imath::V2f* e = &m.coefficients_next[l][(size_t(v) * texels + t) * m.max_rank];
            for (int k = 0; k < m.max_rank; ++k) e[k] = Imath::V2f(in[4 + ch * k], in[5 + ch * k]);
          }
        }
  }
  const std::vector<std::string> lc = light_channels(m.max_rank);
  const size_t L = size_t(m.light_count());
  const std::vector<float> lights = read_data_image_float((fs::path(dir) / k_light_file).string(),
                                                          expect(int(L), m.view_count(), lc));
  for (int v = 0; v < m.view_count(); ++v)
    for (size_t n = 0; n < L; ++n)
      for (int k = 0; k < m.max_rank; ++k)
        m.light_factors[(size_t(v) * L + n) * m.max_rank + k] =
            lights[(size_t(v) * L + n) * lc.size() + k];
}
}  // namespace

uint64_t material_uncompressed_bytes(const ClothMaterial& m) {
  return m.layout().file_bytes(m.max_rank);
}

bool is_material_folder(const std::string& dir) {
  std::error_code ec;
  const fs::path p = fs::path(dir) / k_folder_manifest_name;
  if (!fs::is_regular_file(p, ec)) return false;
  try {
    const json j = parse_json_text(read_text_file(p.string(), "a JSON file"), p.string());
    return j.is_object() && j.contains("format") && j["format"] == k_material_format_name;
  } catch (const InputError&) {
    return false;
  }
}

void write_material(const std::string& dir, const ClothMaterial& m, const MaterialInfo& info) {
  const MaterialLayout layout = m.layout();
  write_folder(dir, "material", material_uncompressed_bytes(m), [&](const fs::path& temp_dir) {
    const std::vector<std::string> channels = level_channels(m.max_rank, m.settings.parts);
    for (int l = 0; l < m.levels(); ++l)
      write_data_image((temp_dir / level_file(l)).string(), layout.atlas_width(l),
                       layout.atlas_height(l), channels, level_pixels(m, l).data());
    write_data_image((temp_dir / k_light_file).string(), m.light_count(), m.view_count(),
                     light_channels(m.max_rank), light_pixels(m).data());
    if (m.addressed()) {
      std::vector<float> blocks(m.crossings.class_of.begin(), m.crossings.class_of.end());
      write_data_image((temp_dir / k_crossings_file).string(), m.crossings.ends, m.crossings.picks,
                       {"block"}, blocks.data());
    }
    write_json_file((temp_dir / k_folder_manifest_name).string(), material_manifest_json(m, info));
  });
}

// Every manifest field checked before any image is read.
ClothMaterial read_material(const std::string& dir, MaterialInfo& info, uint64_t memory_budget,
                            SharedParts parts) {
  const std::string manifest_path = (fs::path(dir) / k_folder_manifest_name).string();
  const json doc = parse_json_text(read_text_file(manifest_path, "a JSON file"), manifest_path);
  const JsonObject top(doc, "", manifest_path);
  check_format(top);
  ClothMaterial m;
  m.settings = read_settings(top, manifest_path);
  top.read("repeat_mm", m.repeat_mm);
  if (!(m.repeat_mm.x > 0 && m.repeat_mm.y > 0 && m.repeat_mm.z > 0))
    top.fail("repeat_mm", "must be positive");
  const JsonObject cloth = top.object("cloth");
  cloth.read("name", info.cloth_name);
  std::string hash;
  cloth.read("hash", hash);
  const std::optional<uint64_t> hash_value = parse_hex16(hash);
  if (!hash_value) cloth.fail(cloth.field("hash"), "must be 16 hex digits, got \"" + hash + "\"");
  m.cloth_hash = *hash_value;
  cloth.read("source", info.source);
  m.optics = read_optics(top.object("optics"));
  m.view_grid.k = m.settings.directions;
  m.light_grid.k = m.settings.light_directions;
  m.light_grid.map = m.settings.light_map;
  if (m.colour_parts()) {
    for (const char* key : {"spec", "colors"})
      if (!cloth.has(key)) cloth.fail(cloth.field(key), "is missing (the parts are colour-free)");
    const ClothSpec spec = cloth_spec_from_json(cloth.object("spec"));
    const JsonObject colors = cloth.object("colors");
    YarnPalette p;
    const JsonObject warp = colors.object("warp"), weft = colors.object("weft");
    warp.read("color", p.warp_color);
    warp.read("colors", p.warp_colors);
    weft.read("color", p.weft_color);
    weft.read("colors", p.weft_colors);
    m.set_cloth(spec, p);
    cloth.read("written_repeats", m.written_repeats);  // absent from older manifests: 1 x 1
    if (!(m.written_repeats.x >= 1.0f && m.written_repeats.y >= 1.0f &&
          m.written_repeats.x == std::round(m.written_repeats.x) &&
          m.written_repeats.y == std::round(m.written_repeats.y)))
      cloth.fail(cloth.field("written_repeats"), "must be two whole numbers of at least 1");
    if (!(std::fabs(thread_repeat_mm(spec, true) / m.repeat_mm.x - 1.0f) < 1e-4f) ||
        !(std::fabs(thread_repeat_mm(spec, false) / m.repeat_mm.y - 1.0f) < 1e-4f))
      cloth.fail(cloth.field("spec"), "gives a repeat other than repeat_mm's");
  }
  if (m.addressed()) read_crossings(dir, top.object("crossings"), m);
  read_table_shape(top, memory_budget, m);
  top.read("parallax_depth_mm", m.parallax_depth_mm);
  if (!(m.parallax_depth_mm >= 0.0f && m.parallax_depth_mm <= m.repeat_mm.z))
    top.fail("parallax_depth_mm",
             "must be in [0, the cloth's thickness " + std::to_string(m.repeat_mm.z) + " mm]");
  read_shard(top, parts, m);
  if (top.has("bake")) {
    const JsonObject bake = top.object("bake");
    bake.read("rays", info.stats.rays);
    bake.read("march_samples", info.stats.march_samples);
    bake.read("fiber_evaluations", info.stats.fiber_evaluations);
  }
  read_images(dir, m);
  return m;
}

}  // namespace clothbake::io
