#include "io/lookup_manifest.h"

#include <limits>

#include "core/util/error.h"
#include "io/json_reader.h"
#include "io/light_json.h"

namespace clothbake::io {

namespace {
using nlohmann::json;

constexpr const char* k_format_name = "clothbake-lookup";
constexpr const char* k_side_names[2] = {"front", "back"};

json vec_json(const Imath::V3f& v) { return json::array({v.x, v.y, v.z}); }
json vec_json(const Imath::V2f& v) { return json::array({v.x, v.y}); }

json mesh_summary_json(const MeshSummary& m) {
  return {{"bounds_min", vec_json(m.bounds_min_world)},
          {"bounds_max", vec_json(m.bounds_max_world)},
          {"uv_min", vec_json(m.uv_min)},
          {"uv_max", vec_json(m.uv_max)},
          {"mean_centre", vec_json(m.mean_centre_world)},
          {"area", m.area_world}};
}

MeshSummary read_mesh_summary(const JsonObject& j) {
  MeshSummary m;
  for (const char* key : {"bounds_min", "bounds_max", "uv_min", "uv_max", "mean_centre", "area"})
    if (!j.has(key)) j.fail(j.field(key), "missing");
  j.read("bounds_min", m.bounds_min_world);
  j.read("bounds_max", m.bounds_max_world);
  j.read("uv_min", m.uv_min);
  j.read("uv_max", m.uv_max);
  j.read("mean_centre", m.mean_centre_world);
  double area = 0.0;  // double, as written: a merge's manifest then equals the whole bake's
  j.read("area", area);
  if (!(area >= 0.0)) j.fail(j.field("area"), "must be >= 0");
  m.area_world = area;
  return m;
}

json settings_json(const BakeSettings& s) {
  return {{"directions", s.directions},
          {"texels", s.texels},
          {"spp", s.spp},
          {"adaptive", s.adaptive},
          {"texels_per_pixel", s.texels_per_pixel},
          {"min_texels", s.min_texels},
          {"max_texels", s.max_texels},
          {"quad_begin", s.quad_begin},
          {"quad_end", s.quad_end},
          {"seed", s.seed}};
}

std::string type_name(const json& v) { return json_type_name(v); }

const json& required(const JsonObject& j, const char* key) {
  if (!j.has(key)) j.fail(j.field(key), "missing");
  return j.raw(key);
}

std::string required_string(const JsonObject& j, const char* key) {
  required(j, key);
  std::string s;
  j.read(key, s);
  return s;
}

int required_int(const JsonObject& j, const char* key) {
  required(j, key);
  int v = 0;
  j.read(key, v);
  return v;
}

/// An array of `n` integers at `field`.
std::vector<int> int_array(const JsonObject& j, const json& v, const std::string& field, size_t n) {
  if (!v.is_array() || v.size() != n)
    j.fail(field, "expected an array of " + std::to_string(n) + " integers, got " + type_name(v) +
                      (v.is_array() ? " of " + std::to_string(v.size()) : ""));
  std::vector<int> out;
  for (size_t i = 0; i < n; ++i) {
    // Unsigned first: one above INT64_MAX would wrap to a negative int64_t.
    const bool fits = v[i].is_number_unsigned()
                          ? v[i].get<uint64_t>() <= uint64_t(std::numeric_limits<int>::max())
                          : v[i].is_number_integer() &&
                                v[i].get<int64_t>() >= std::numeric_limits<int>::min() &&
                                v[i].get<int64_t>() <= std::numeric_limits<int>::max();
    if (!fits)
      j.fail(field + "[" + std::to_string(i) + "]", "expected an integer, got " + type_name(v[i]));
    out.push_back(int(v[i].get<int64_t>()));
  }
  return out;
}

BakeSettings read_settings(const JsonObject& j) {
  BakeSettings s;
  j.read("directions", s.directions);
  j.read("texels", s.texels);
  j.read("spp", s.spp);
  if (j.has("adaptive")) {
    if (!j.raw("adaptive").is_boolean())
      j.fail(j.field("adaptive"), "expected true or false, got " + type_name(j.raw("adaptive")));
    s.adaptive = j.raw("adaptive").get<bool>();
  }
  j.read("texels_per_pixel", s.texels_per_pixel);
  j.read("min_texels", s.min_texels);
  j.read("max_texels", s.max_texels);
  j.read("quad_begin", s.quad_begin);
  j.read("quad_end", s.quad_end);
  j.read("seed", s.seed);
  return s;
}

/// Step 1: what this folder is: format, version, scene, direction map,
/// settings and statistics (into `out`); returns the direction grid.
DirectionGrid read_header(const JsonObject& top, const std::string& expected_scene_hash,
                          LookupInfo& out) {
  const std::string format = required_string(top, "format");
  if (format != k_format_name)
    top.fail("format", "expected \"" + std::string(k_format_name) + "\", got \"" + format +
                           "\"; this is not a clothbake lookup");
  const int version = required_int(top, "version");
  if (version != k_lookup_format_version)
    top.fail("version", "this lookup has format version " + std::to_string(version) +
                            "; this clothbake reads version " +
                            std::to_string(k_lookup_format_version));
  top.read("scene", out.scene_path);
  out.scene_hash = required_string(top, "scene_hash");
  if (!expected_scene_hash.empty() && out.scene_hash != expected_scene_hash)
    top.fail("scene_hash", "this lookup was baked for another scene (hash " + out.scene_hash +
                               ", expected " + expected_scene_hash + "); bake again");

  const JsonObject map = top.object("direction_map");
  const std::string map_type = required_string(map, "type");
  if (map_type != "hemi-octahedral" && map_type != "polar")
    map.fail(map.field("type"),
             "expected \"polar\" or \"hemi-octahedral\", got \"" + map_type + "\"");
  const DirectionMap direction_map =
      map_type == "polar" ? DirectionMap::Polar : DirectionMap::HemiOctahedral;
  const int k = required_int(map, "k");
  if (k < k_min_directions || k > k_max_directions)
    map.fail(map.field("k"), "must be in [" + std::to_string(k_min_directions) + ", " +
                                 std::to_string(k_max_directions) + "], got " + std::to_string(k));
  if (required(map, "sides") != json::array({"front", "back"}))
    map.fail(map.field("sides"), "expected [\"front\", \"back\"]");
  const std::string expected_nodes = direction_map == DirectionMap::Polar ? "polar" : "corners";
  if (const std::string nodes = required_string(map, "nodes"); nodes != expected_nodes)
    map.fail(map.field("nodes"), "expected \"" + expected_nodes + "\", got \"" + nodes + "\"");

  if (top.has("settings")) out.settings = read_settings(top.object("settings"));
  if (top.has("statistics")) out.statistics = top.raw("statistics");
  DirectionGrid dirs;
  dirs.k = k;
  dirs.map = direction_map;
  return dirs;
}

/// An object's quads, gutter, square sizes and baked flags.
LookupTable read_object_layout(const JsonObject& obj, const DirectionGrid& dirs,
                               std::string& cloth_hash) {
  LookupTable t;
  t.dirs = dirs;
  obj.read("cloth_hash", cloth_hash);
  const int quads = required_int(obj, "quads");
  if (quads < 0) obj.fail(obj.field("quads"), "must be >= 0");
  t.gutter = required_int(obj, "gutter");
  if (t.gutter < 0 || t.gutter > 64) obj.fail(obj.field("gutter"), "must be in [0, 64]");

  const json& sizes = required(obj, "sizes");
  if (!sizes.is_array() || sizes.size() != size_t(quads))
    obj.fail(obj.field("sizes"),
             "expected an array of " + std::to_string(quads) + " integers (one per quad), got " +
                 type_name(sizes) +
                 (sizes.is_array() ? " of " + std::to_string(sizes.size()) : ""));
  t.sizes = int_array(obj, sizes, obj.field("sizes"), size_t(quads));
  for (int q = 0; q < quads; ++q)
    if (t.sizes[q] < 0 || t.sizes[q] > 65536)
      obj.fail(obj.field("sizes") + "[" + std::to_string(q) + "]",
               "must be in [0, 65536], got " + std::to_string(t.sizes[q]));

  const json& baked = required(obj, "baked");
  if (!baked.is_array() || baked.size() != size_t(quads))
    obj.fail(obj.field("baked"),
             "expected an array of " + std::to_string(quads) + " strings (one per quad), got " +
                 type_name(baked) +
                 (baked.is_array() ? " of " + std::to_string(baked.size()) : ""));
  const int nodes = t.node_count();
  // Every flag string first: quads x nodes is only allocated once the
  // manifest holds that many flags (a short file must not claim gigabytes).
  for (size_t q = 0; q < baked.size(); ++q)
    if (!baked[q].is_string() || baked[q].get_ref<const std::string&>().size() != size_t(nodes))
      obj.fail(obj.field("baked") + "[" + std::to_string(q) + "]",
               "expected a string of " + std::to_string(nodes) + " '0'/'1' (2 K^2)");
  t.baked.assign(size_t(quads) * nodes, 0);
  for (size_t q = 0; q < baked.size(); ++q) {
    const std::string field = obj.field("baked") + "[" + std::to_string(q) + "]";
    const std::string& flags = baked[q].get_ref<const std::string&>();
    for (int n = 0; n < nodes; ++n) {
      if (flags[n] != '0' && flags[n] != '1')
        obj.fail(field, "character " + std::to_string(n) + " is neither '0' nor '1'");
      t.baked[q * nodes + n] = flags[n] == '1';
    }
  }
  return t;
}

/// One side's atlas: its size and squares (into `t`); returns the name of
/// its image file.
std::string read_side_layout(const JsonObject& sj, int side, const char* key, LookupTable& t) {
  const int quads = t.quad_count(), nodes = t.node_count();
  const std::vector<int> size = int_array(sj, required(sj, "size"), sj.field("size"), 2);
  if (size[0] < 1 || size[1] < 1 || size[0] > 65536 || size[1] > 65536)
    sj.fail(sj.field("size"), "must be two integers in [1, 65536]");
  LookupAtlas& atlas = t.atlases[side];
  atlas.width = size[0];
  atlas.height = size[1];
  const json& squares = required(sj, "squares");
  if (!squares.is_array()) sj.fail(sj.field("squares"), "expected an array of [quad, node, x, y]");
  for (size_t i = 0; i < squares.size(); ++i) {
    const std::string field = sj.field("squares") + "[" + std::to_string(i) + "]";
    const std::vector<int> v = int_array(sj, squares[i], field, 4);
    const int q = v[0], n = v[1], x = v[2], y = v[3];
    if (q < 0 || q >= quads) sj.fail(field, "quad " + std::to_string(q) + " out of range");
    if (n < side * t.dirs.nodes_per_side() || n >= (side + 1) * t.dirs.nodes_per_side())
      sj.fail(field, "node " + std::to_string(n) + " is not a node of the " + key + " side");
    const int w = t.sizes[q];
    if (w == 0) sj.fail(field, "quad " + std::to_string(q) + " has size 0");
    // In 64 bits: x - gutter overflows an int for x near INT_MIN.
    if (int64_t(x) - t.gutter < 0 || int64_t(y) - t.gutter < 0 ||
        int64_t(x) + w + t.gutter > atlas.width || int64_t(y) + w + t.gutter > atlas.height)
      sj.fail(field, "the square and its gutter do not fit in the " + std::to_string(atlas.width) +
                         " x " + std::to_string(atlas.height) + " atlas");
    SquareSlot& slot = t.slots[size_t(q) * nodes + n];
    if (slot.valid()) sj.fail(field, "a second square for the same quad and node");
    slot = SquareSlot{x, y};
  }
  const json& file = required(sj, "file");
  if (!file.is_string()) sj.fail(sj.field("file"), "expected a file name, got " + type_name(file));
  const std::string name = file.get<std::string>();
  if (name.empty() || name.find_first_of("/\\") != std::string::npos || name[0] == '.')
    sj.fail(sj.field("file"), "must be a file name inside the lookup folder, got \"" + name + "\"");
  return name;
}

}  // namespace

std::string lookup_image_name(size_t object, int side) {
  return "object" + std::to_string(object) + "_side" + std::to_string(side) + ".exr";
}

bool side_has_atlas(const LookupTable& t, int side) { return t.atlases[side].width > 0; }

json lookup_manifest_json(const std::vector<LookupTable>& tables, const LookupInfo& info,
                          const Scene& scene) {
  const int k = tables.empty() ? 0 : tables[0].dirs.k;
  json m;
  m["format"] = k_format_name;
  m["version"] = k_lookup_format_version;
  m["scene"] = info.scene_path;
  m["scene_hash"] = info.scene_hash;
  const bool polar = !tables.empty() && tables[0].dirs.map == DirectionMap::Polar;
  m["direction_map"] = {{"type", polar ? "polar" : "hemi-octahedral"},
                        {"k", k},
                        {"sides", json::array({"front", "back"})},
                        {"nodes", polar ? "polar" : "corners"}};
  m["settings"] = settings_json(info.settings);
  m["lights"] = json::array();
  for (const Light& l : scene.lights) m["lights"].push_back(stored_light_json(l));
  m["objects"] = json::array();
  for (size_t o = 0; o < tables.size(); ++o) {
    const LookupTable& t = tables[o];
    json obj;
    obj["name"] = o < scene.objects.size() ? scene.objects[o].name : std::string();
    obj["cloth_hash"] = o < info.cloth_hashes.size() ? info.cloth_hashes[o] : std::string();
    obj["quads"] = t.quad_count();
    if (o < info.meshes.size() && info.meshes[o]) obj["mesh"] = mesh_summary_json(*info.meshes[o]);
    obj["gutter"] = t.gutter;
    obj["sizes"] = t.sizes;
    json baked = json::array();
    for (int q = 0; q < t.quad_count(); ++q) {
      std::string flags(size_t(t.node_count()), '0');
      for (int n = 0; n < t.node_count(); ++n)
        if (t.is_baked(q, n)) flags[n] = '1';
      baked.push_back(std::move(flags));
    }
    obj["baked"] = std::move(baked);
    json sides = json::object();
    for (int side = 0; side < 2; ++side) {
      if (!side_has_atlas(t, side)) {
        sides[k_side_names[side]] = nullptr;
        continue;
      }
      json squares = json::array();
      for (int q = 0; q < t.quad_count(); ++q)
        for (int n = side * t.dirs.nodes_per_side(); n < (side + 1) * t.dirs.nodes_per_side(); ++n)
          if (const SquareSlot& sl = t.slot(q, n); sl.valid())
            squares.push_back(json::array({q, n, sl.x, sl.y}));
      sides[k_side_names[side]] = {
          {"file", lookup_image_name(o, side)},
          {"size", json::array({t.atlases[side].width, t.atlases[side].height})},
          {"squares", std::move(squares)}};
    }
    obj["sides"] = std::move(sides);
    m["objects"].push_back(std::move(obj));
  }
  m["statistics"] = info.statistics.is_null() ? json::object() : info.statistics;
  return m;
}

LookupManifest parse_lookup_manifest(const std::string& manifest_text,
                                     const std::string& manifest_path,
                                     const std::string& expected_scene_hash) {
  const json doc = parse_json_text(manifest_text, manifest_path);
  const JsonObject top(doc, "", manifest_path);
  LookupManifest m;
  const DirectionGrid dirs = read_header(top, expected_scene_hash, m.info);

  // Step 2: each object's layout and flags, then each side's atlas.
  const json& objects = required(top, "objects");
  if (!objects.is_array()) top.fail("objects", "expected an array, got " + type_name(objects));
  for (size_t o = 0; o < objects.size(); ++o) {
    const JsonObject obj(objects[o], "objects[" + std::to_string(o) + "]", manifest_path);
    std::string cloth_hash;
    LookupTable t = read_object_layout(obj, dirs, cloth_hash);
    const int quads = t.quad_count(), nodes = t.node_count();
    t.slots.assign(size_t(quads) * nodes, SquareSlot{});
    std::array<std::string, 2> files, fields;
    const JsonObject sides = obj.object("sides");
    for (int side = 0; side < 2; ++side) {
      const char* key = k_side_names[side];
      if (!sides.has(key) || sides.raw(key).is_null()) continue;
      files[side] = read_side_layout(sides.object(key), side, key, t);
      fields[side] = sides.field(key);
    }
    for (int q = 0; q < quads; ++q)
      for (int n = 0; n < nodes; ++n)
        if (t.is_baked(q, n) && !t.slot(q, n).valid())
          obj.fail(obj.field("baked") + "[" + std::to_string(q) + "]",
                   "node " + std::to_string(n) + " is marked baked but has no square in " +
                       obj.field("sides") + "." + k_side_names[t.side_of(n)] + ".squares");
    m.info.cloth_hashes.push_back(cloth_hash);
    m.info.quad_counts.push_back(quads);
    m.info.meshes.push_back(obj.has("mesh") ? std::optional(read_mesh_summary(obj.object("mesh")))
                                            : std::nullopt);
    m.tables.push_back(std::move(t));
    m.image_files.push_back(files);
    m.image_fields.push_back(fields);
  }
  return m;
}

Scene parse_lookup_scene(const std::string& manifest_text, const std::string& manifest_path) {
  const json doc = parse_json_text(manifest_text, manifest_path);
  const JsonObject top(doc, "", manifest_path);
  Scene scene;
  if (top.has("lights")) {
    const json& lights = top.raw("lights");
    if (!lights.is_array()) top.fail("lights", "expected an array, got " + type_name(lights));
    for (size_t i = 0; i < lights.size(); ++i)
      scene.lights.push_back(
          read_light(JsonObject(lights[i], "lights[" + std::to_string(i) + "]", manifest_path),
                     LightSpelling::Stored));
  }
  const json& objects = required(top, "objects");
  if (!objects.is_array()) top.fail("objects", "expected an array, got " + type_name(objects));
  for (size_t o = 0; o < objects.size(); ++o) {
    const JsonObject j(objects[o], "objects[" + std::to_string(o) + "]", manifest_path);
    ClothObject object;
    j.read("name", object.name);
    scene.objects.push_back(std::move(object));
  }
  return scene;
}

}  // namespace clothbake::io
