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

#include <OpenImageIO/imageio.h>

#include "core/error.h"
#include "core/random.h"
#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {
namespace fs = std::filesystem;
namespace oiio = OIIO;
using nlohmann::json;

constexpr const char* k_format_name = "clothbake-lookup";
constexpr const char* k_manifest_name = "manifest.json";
constexpr const char* k_side_names[2] = {"front", "back"};

std::string image_name(size_t object, int side) {
  return "object" + std::to_string(object) + "_side" + std::to_string(side) + ".exr";
}

/// True if the side's atlas holds any square (it then has an image file).
bool side_has_atlas(const LookupTable& t, int side) { return t.atlases[side].width > 0; }

// ---------------------------------------------------------------------------
// Scene fingerprint

/// Folds values into one 64-bit hash; floats by their bits, so the hash is
/// exact (no rounding) and the same on every platform with IEEE floats.
class Fingerprint {
 public:
  void add(uint64_t x) { m_h = hash_key(m_h, x); }
  void add(int x) { add(uint64_t(uint32_t(x))); }
  void add(float x) { add(uint64_t(std::bit_cast<uint32_t>(x))); }
  void add(const Imath::V3f& v) {
    add(v.x);
    add(v.y);
    add(v.z);
  }
  void add(const Imath::V2f& v) {
    add(v.x);
    add(v.y);
  }
  void add(const std::string& s) {
    add(uint64_t(s.size()));
    for (char c : s) add(uint64_t(uint8_t(c)));
  }
  uint64_t value() const { return m_h; }

 private:
  uint64_t m_h = 0x636C6F746862616Bull;  // "clothbak"
};

void add_yarn(Fingerprint& f, const YarnSpec& y) {
  f.add(y.spacing_mm);
  f.add(y.width_mm);
  f.add(y.thickness_mm);
  f.add(y.color);
  f.add(y.twist_deg);
  f.add(y.ply_pitch_mm);
}

// Every field of ClothSpec: keep in step with core/cloth_spec.h.
void add_cloth(Fingerprint& f, const ClothSpec& c) {
  f.add(c.pattern);
  f.add(uint64_t(c.draft.size()));
  for (const std::vector<int>& row : c.draft) {
    f.add(uint64_t(row.size()));
    for (int v : row) f.add(v);
  }
  add_yarn(f, c.warp);
  add_yarn(f, c.weft);
  f.add(c.crimp);
  f.add(c.angle_spread_deg);
  const DensitySpec& d = c.density;
  for (float v : {d.core, d.edge, d.falloff, d.top_factor, d.noise_amplitude, d.noise_scale_mm})
    f.add(v);
  const ShadingSpec& s = c.shading;
  for (float v : {s.specular_top, s.specular_bottom, s.diffuse_top, s.diffuse_bottom, s.exponent,
                  s.variation, s.fiber_aspect})
    f.add(v);
  const ResolutionSpec& r = c.resolution;
  for (int v : {r.cells_x, r.cells_y, r.layers, r.supersample}) f.add(v);
  f.add(c.seed);
}

// ---------------------------------------------------------------------------
// Writing

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
  float area = 0.0f;
  j.read("area", area);
  if (!(area >= 0.0f)) j.fail(j.field("area"), "must be >= 0");
  m.area_world = area;
  return m;
}

json light_json(const Light& l) {
  auto v3 = [](const Imath::V3f& v) { return json::array({v.x, v.y, v.z}); };
  json j;
  if (l.type == LightType::Directional) {
    j["type"] = "directional";
    j["to_light"] = v3(l.to_light_world);
  } else {
    j["type"] = "point";
    j["position"] = v3(l.position_world);
  }
  j["color"] = v3(l.color);
  j["intensity"] = l.intensity;
  return j;
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

json manifest_json(const std::vector<LookupTable>& tables, const LookupInfo& info,
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
  for (const Light& l : scene.lights) m["lights"].push_back(light_json(l));
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
          {"file", image_name(o, side)},
          {"size", json::array({t.atlases[side].width, t.atlases[side].height})},
          {"squares", std::move(squares)}};
    }
    obj["sides"] = std::move(sides);
    m["objects"].push_back(std::move(obj));
  }
  m["statistics"] = info.statistics.is_null() ? json::object() : info.statistics;
  return m;
}

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
  const size_t width = size_t(atlas.width), height = size_t(atlas.height);
  const std::vector<Imath::half>& pixels = atlas.pixels;
  oiio::ImageSpec spec(int(width), int(height), 4, oiio::TypeDesc::HALF);
  spec.channelnames = {"R", "G", "B", "A"};
  spec.alpha_channel = 3;
  spec.attribute("compression", "zip");
  // No capture date: the same lookup must give the same bytes (merge == whole bake).
  spec.attribute("DateTime", "");
  auto out = oiio::ImageOutput::create(path);
  if (!out) throw InputError("", oiio::geterror(), path);
  if (!out->open(path, spec) || !out->write_image(oiio::TypeDesc::HALF, pixels.data()) ||
      !out->close()) {
    const std::string why = out->geterror();  // geterror() clears the message
    throw InputError("", why.empty() ? "write error" : why, path);
  }
}

void write_manifest(const std::string& path, const json& manifest) {
  errno = 0;
  std::ofstream f(path, std::ios::binary);
  f << manifest.dump(2) << "\n";
  f.close();
  if (!f) throw InputError("", errno != 0 ? std::strerror(errno) : "write error", path);
}

// ---------------------------------------------------------------------------
// Reading

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

/// Reads a side atlas of want_w x want_h RGBA pixels, as halves.
std::vector<Imath::half> read_side_image(const std::string& path, const std::string& named_by,
                                         int64_t want_w, int64_t want_h) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(
        "", "cannot read the lookup image: missing (named by " + named_by + " in manifest.json)",
        path);
  auto in = oiio::ImageInput::open(path);
  if (!in) throw InputError("", "cannot read the lookup image: " + oiio::geterror(), path);
  const oiio::ImageSpec& spec = in->spec();
  if (spec.nchannels != 4)
    throw InputError(
        "",
        "has " + std::to_string(spec.nchannels) + " channels; a lookup image has 4 (R, G, B, A)",
        path);
  if (spec.width != want_w || spec.height != want_h || spec.depth != 1)
    throw InputError("",
                     "is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                         " pixels; the manifest (" + named_by + ".size) says " +
                         std::to_string(want_w) + " x " + std::to_string(want_h),
                     path);
  std::vector<Imath::half> pixels(size_t(want_w) * size_t(want_h) * 4);
  if (!in->read_image(0, 0, 0, 4, oiio::TypeDesc::HALF, pixels.data())) {
    std::string why = in->geterror();
    if (why.empty()) why = "corrupt or truncated file";
    throw InputError("", "cannot read the lookup image: " + why, path);
  }
  in->close();
  return pixels;
}

/// The first layout field in which two tables of one K differ (empty if none):
/// parts of one bake share everything but their flags and texels.
std::string layout_mismatch(const LookupTable& a, const LookupTable& b) {
  if (a.gutter != b.gutter) return "gutter";
  if (a.sizes != b.sizes) return "sizes";
  for (int side = 0; side < 2; ++side) {
    const LookupAtlas &aa = a.atlases[side], &ab = b.atlases[side];
    if (aa.width != ab.width || aa.height != ab.height)
      return std::string("sides.") + k_side_names[side] + ".size";
  }
  for (size_t i = 0; i < a.slots.size(); ++i)
    if (a.slots[i].x != b.slots[i].x || a.slots[i].y != b.slots[i].y) return "sides (squares)";
  return {};
}
}  // namespace

std::string scene_fingerprint(const Scene& scene) {
  Fingerprint f;
  // Objects: geometry, mapping into the texture, and the cloth itself.
  f.add(uint64_t(scene.objects.size()));
  for (const ClothObject& o : scene.objects) {
    const QuadMesh& m = o.mesh;
    f.add(uint64_t(m.positions_world.size()));
    for (const Imath::V3f& p : m.positions_world) f.add(p);
    f.add(uint64_t(m.uvs.size()));
    for (const Imath::V2f& uv : m.uvs) f.add(uv);
    f.add(uint64_t(m.quads.size()));
    for (const QuadMesh::Quad& q : m.quads)
      for (int c = 0; c < 4; ++c) {
        f.add(q.position[c]);
        f.add(q.uv[c]);
      }
    f.add(o.repeats_per_uv);
    f.add(o.thickness_world);
    f.add(o.extinction_per_mm);
    f.add(o.isotropic_albedo);
    add_cloth(f, o.cloth);
    // A texture read from a VDB: its contents, so an edited file is a new scene.
    if (o.volume) f.add(o.volume->content_hash());
  }
  // Lights: only what the light's type uses.
  f.add(uint64_t(scene.lights.size()));
  for (const Light& l : scene.lights) {
    f.add(int(l.type));
    f.add(l.type == LightType::Directional ? l.to_light_world : l.position_world);
    f.add(l.color);
    f.add(l.intensity);
  }
  // Render settings that change a march (not spp: the bake has its own).
  const RenderSettings& s = scene.settings;
  f.add(s.step_cells);
  f.add(int(s.fiber_model));
  f.add(s.fiber_samples);
  f.add(int(s.transmittance));
  f.add(int(s.shading));
  f.add(s.cutoff);
  f.add(s.seed);
  f.add(s.light_roulette);  // changes the bake's bytes (not its expectation), as the seed does

  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(f.value()));
  return hex;
}

void check_lookup_destination(const std::string& dir) {
  std::error_code ec;
  fs::path final_dir(dir);
  if (!final_dir.has_filename()) final_dir = final_dir.parent_path();  // "out/" -> "out"
  // The swap renames inside the parent: it must be writable (if it exists yet).
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  if (fs::is_directory(parent, ec) && ::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InputError(
        "", "cannot write in the folder " + parent.string() + ": " + std::strerror(errno), dir);
  if (!fs::exists(final_dir, ec)) return;
  if (!fs::is_directory(final_dir, ec)) throw InputError("", "exists and is not a folder", dir);
  if (!fs::is_empty(final_dir, ec) && !fs::exists(final_dir / k_manifest_name, ec))
    throw InputError("", "exists and is not a lookup folder (no manifest.json); not replacing it",
                     dir);
}

void write_lookup(const std::string& dir, const std::vector<LookupTable>& tables,
                  const LookupInfo& info, const Scene& scene) {
  fs::path final_dir = fs::path(dir);
  if (!final_dir.has_filename()) final_dir = final_dir.parent_path();  // "out/" -> "out"
  if (final_dir.empty()) throw InputError("", "empty output folder name", dir);
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  const std::string pid = std::to_string(::getpid());
  const fs::path temp_dir = parent / (final_dir.filename().string() + ".tmp-" + pid);
  const fs::path old_dir = parent / (final_dir.filename().string() + ".old-" + pid);

  // Refuse to replace anything but a lookup folder (or an empty one): the
  // swap below deletes the previous contents.
  check_lookup_destination(dir);
  std::error_code ec;

  // Step 1: everything into the temporary sibling folder, the manifest last.
  const int k = tables.empty() ? 0 : tables[0].dirs.k;
  for (size_t o = 0; o < tables.size(); ++o) check_table(tables[o], o, k);
  fs::remove_all(temp_dir, ec);                    // left over by a crashed run with our pid
  UnfinishedOutput unfinished(temp_dir.string());  // removed on a throw or an interrupt
  fs::create_directories(temp_dir, ec);
  if (ec)
    throw InputError(
        "", "cannot create the temporary folder " + temp_dir.string() + ": " + ec.message(), dir);
  try {
    for (size_t o = 0; o < tables.size(); ++o)
      for (int side = 0; side < 2; ++side)
        if (side_has_atlas(tables[o], side))
          write_side_image((temp_dir / image_name(o, side)).string(), tables[o], side);
    write_manifest((temp_dir / k_manifest_name).string(), manifest_json(tables, info, scene));
  } catch (const InputError& e) {
    // Name the folder the user asked for, not the temporary one.
    throw InputError("",
                     "cannot write " + fs::path(e.file()).filename().string() + ": " + e.message() +
                         "; nothing under this name was changed",
                     dir);
  }

  // Step 2: swap it in; the previous folder survives until the new one is in
  // place. Where the file system can, one exchange of the two names (so not
  // even a kill -9 finds the final name missing); else two renames, between
  // which an interrupt cannot fall (publish holds the interrupt lock).
  unfinished.publish([&] {
    const bool had_old = fs::exists(final_dir, ec);
    if (had_old && ::renameat2(AT_FDCWD, temp_dir.c_str(), AT_FDCWD, final_dir.c_str(),
                               RENAME_EXCHANGE) == 0) {
      fs::remove_all(temp_dir, ec);  // now the previous lookup
      return;
    }
    if (had_old) {
      fs::remove_all(old_dir, ec);
      fs::rename(final_dir, old_dir, ec);
      if (ec) throw InputError("", "cannot move the previous lookup aside: " + ec.message(), dir);
    }
    fs::rename(temp_dir, final_dir, ec);
    if (ec) {
      const std::string why = ec.message();
      if (had_old) fs::rename(old_dir, final_dir, ec);
      throw InputError("", "cannot move the finished lookup into place: " + why, dir);
    }
    if (had_old) fs::remove_all(old_dir, ec);
  });
}

std::vector<LookupTable> read_lookup(const std::string& dir, LookupInfo& info,
                                     const std::string& expected_scene_hash) {
  const std::string manifest_path = (fs::path(dir) / k_manifest_name).string();
  return read_lookup_manifest(read_text_file(manifest_path, "a JSON file"), dir, info,
                              expected_scene_hash);
}

std::vector<LookupTable> read_lookup_manifest(const std::string& manifest_text,
                                              const std::string& dir, LookupInfo& info,
                                              const std::string& expected_scene_hash) {
  const std::string manifest_path = (fs::path(dir) / k_manifest_name).string();
  const json doc = parse_json_text(manifest_text, manifest_path);
  const JsonObject top(doc, "", manifest_path);

  // Step 1: what this folder is.
  const std::string format = required_string(top, "format");
  if (format != k_format_name)
    top.fail("format", "expected \"" + std::string(k_format_name) + "\", got \"" + format +
                           "\"; this is not a clothbake lookup");
  const int version = required_int(top, "version");
  if (version != k_lookup_format_version)
    top.fail("version", "this lookup has format version " + std::to_string(version) +
                            "; this clothbake reads version " +
                            std::to_string(k_lookup_format_version));
  LookupInfo out;
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
  if (k < 2 || k > 64) map.fail(map.field("k"), "must be in [2, 64], got " + std::to_string(k));
  if (required(map, "sides") != json::array({"front", "back"}))
    map.fail(map.field("sides"), "expected [\"front\", \"back\"]");
  const std::string expected_nodes = direction_map == DirectionMap::Polar ? "polar" : "corners";
  if (const std::string nodes = required_string(map, "nodes"); nodes != expected_nodes)
    map.fail(map.field("nodes"), "expected \"" + expected_nodes + "\", got \"" + nodes + "\"");

  if (top.has("settings")) out.settings = read_settings(top.object("settings"));
  if (top.has("statistics")) out.statistics = top.raw("statistics");

  // Step 2: each object's layout and flags, then its images.
  const json& objects = required(top, "objects");
  if (!objects.is_array()) top.fail("objects", "expected an array, got " + type_name(objects));
  std::vector<LookupTable> tables;
  for (size_t o = 0; o < objects.size(); ++o) {
    const JsonObject obj(objects[o], "objects[" + std::to_string(o) + "]", manifest_path);
    LookupTable t;
    t.dirs.k = k;
    t.dirs.map = direction_map;
    std::string cloth_hash;
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

    // Each side's atlas: its size and squares, then its pixels.
    t.slots.assign(size_t(quads) * nodes, SquareSlot{});
    const JsonObject sides = obj.object("sides");
    for (int side = 0; side < 2; ++side) {
      const char* key = k_side_names[side];
      if (!sides.has(key) || sides.raw(key).is_null()) continue;
      const JsonObject sj = sides.object(key);
      const std::vector<int> size = int_array(sj, required(sj, "size"), sj.field("size"), 2);
      if (size[0] < 1 || size[1] < 1 || size[0] > 65536 || size[1] > 65536)
        sj.fail(sj.field("size"), "must be two integers in [1, 65536]");
      LookupAtlas& atlas = t.atlases[side];
      atlas.width = size[0];
      atlas.height = size[1];
      const json& squares = required(sj, "squares");
      if (!squares.is_array())
        sj.fail(sj.field("squares"), "expected an array of [quad, node, x, y]");
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
          sj.fail(field, "the square and its gutter do not fit in the " +
                             std::to_string(atlas.width) + " x " + std::to_string(atlas.height) +
                             " atlas");
        SquareSlot& slot = t.slots[size_t(q) * nodes + n];
        if (slot.valid()) sj.fail(field, "a second square for the same quad and node");
        slot = SquareSlot{x, y};
      }
      const json& file = required(sj, "file");
      if (!file.is_string())
        sj.fail(sj.field("file"), "expected a file name, got " + type_name(file));
      const std::string name = file.get<std::string>();
      if (name.empty() || name.find_first_of("/\\") != std::string::npos || name[0] == '.')
        sj.fail(sj.field("file"),
                "must be a file name inside the lookup folder, got \"" + name + "\"");
      atlas.pixels = read_side_image((fs::path(dir) / name).string(), sides.field(key), atlas.width,
                                     atlas.height);
    }
    for (int q = 0; q < quads; ++q)
      for (int n = 0; n < nodes; ++n)
        if (t.is_baked(q, n) && !t.slot(q, n).valid())
          obj.fail(obj.field("baked") + "[" + std::to_string(q) + "]",
                   "node " + std::to_string(n) + " is marked baked but has no square in " +
                       obj.field("sides") + "." + k_side_names[t.side_of(n)] + ".squares");
    out.cloth_hashes.push_back(cloth_hash);
    out.quad_counts.push_back(quads);
    out.meshes.push_back(obj.has("mesh") ? std::optional(read_mesh_summary(obj.object("mesh")))
                                         : std::nullopt);
    tables.push_back(std::move(t));
  }
  info = std::move(out);
  return tables;
}

Scene read_lookup_scene(const std::string& dir) {
  const std::string manifest_path = (fs::path(dir) / k_manifest_name).string();
  return read_lookup_scene_manifest(read_text_file(manifest_path, "a JSON file"), dir);
}

Scene read_lookup_scene_manifest(const std::string& manifest_text, const std::string& dir) {
  const std::string manifest_path = (fs::path(dir) / k_manifest_name).string();
  const json doc = parse_json_text(manifest_text, manifest_path);
  const JsonObject top(doc, "", manifest_path);
  Scene scene;
  if (top.has("lights")) {
    const json& lights = top.raw("lights");
    if (!lights.is_array()) top.fail("lights", "expected an array, got " + type_name(lights));
    for (size_t i = 0; i < lights.size(); ++i) {
      const JsonObject j(lights[i], "lights[" + std::to_string(i) + "]", manifest_path);
      Light l;
      const std::string type = required_string(j, "type");
      if (type == "directional") {
        l.type = LightType::Directional;
        j.read("to_light", l.to_light_world);
      } else if (type == "point") {
        l.type = LightType::Point;
        j.read("position", l.position_world);
      } else {
        j.fail(j.field("type"), "expected \"directional\" or \"point\", got \"" + type + "\"");
      }
      j.read("color", l.color);
      j.read("intensity", l.intensity);
      scene.lights.push_back(l);
    }
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
                       what + " differs from " + (fs::path(dirs[0]) / k_manifest_name).string() +
                           detail + "; parts to merge must come from one scene and one bake",
                       (fs::path(dirs[p]) / k_manifest_name).string());
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

  // Step 2: union of the flags, then each baked square (with its gutter)
  // from the first part that baked it.
  for (size_t o = 0; o < merged.size(); ++o) {
    LookupTable& t = merged[o];
    std::fill(t.baked.begin(), t.baked.end(), 0);
    for (const auto& part : parts)
      for (size_t i = 0; i < t.baked.size(); ++i) t.baked[i] |= part[o].baked[i];
    t.allocate_atlases();
    const int nodes = t.node_count(), g = t.gutter;
    for (int q = 0; q < t.quad_count(); ++q)
      for (int n = 0; n < nodes; ++n)
        for (const auto& part : parts) {
          if (!part[o].is_baked(q, n)) continue;
          const int w = t.sizes[q] + 2 * g;
          for (int b = -g; b < t.sizes[q] + g; ++b)
            std::copy_n(part[o].texel(q, n, -g, b), size_t(w) * 4, t.texel(q, n, -g, b));
          break;
        }
  }

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
