#include "io/scene_json.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <utility>

#include <Imath/ImathVec.h>

#include "core/march/volume_march.h"
#include "core/scene/scene_checks.h"
#include "core/util/error.h"
#include "io/cloth_spec_json.h"
#include "io/enum_names.h"
#include "io/json_reader.h"
#include "io/light_json.h"
#include "io/obj_reader.h"
#include "io/text_file.h"
#include "io/vdb_reader.h"

namespace clothbake::io {

namespace {

namespace fs = std::filesystem;
using Imath::V3d;
using Imath::V3f;

constexpr int kMaxResolution = 16384;
constexpr int kMaxSamples = 65536;

std::string type_name(const nlohmann::json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "a boolean";
  if (v.is_null()) return "null";
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  return "an object";
}

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string fmt(const V3f& v) { return "[" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + "]"; }

V3d to_double(const V3f& v) { return V3d(v.x, v.y, v.z); }

fs::path relative_to(const std::string& scene_path, const std::string& rel) {
  const fs::path p(rel);
  return p.is_absolute() ? p : fs::path(scene_path).parent_path() / p;
}

/// Maps the string at `key` onto an enum value, listing the allowed names on error.
/// The camera's spellings (the shared ones are in io/enum_names.h).
constexpr EnumNames<FovAxis, 2> k_fov_axis_names{{
    {"horizontal", FovAxis::Horizontal},
    {"vertical", FovAxis::Vertical},
}};

void require_non_negative(const JsonObject& j, const char* key, const V3f& v) {
  if (v.x < 0.0f || v.y < 0.0f || v.z < 0.0f)
    j.fail(j.field(key), "must be >= 0 in every channel, got " + fmt(v));
}

void read_resolution(const JsonObject& j, int& width, int& height) {
  const nlohmann::json& v = j.raw("resolution");
  const std::string field = j.field("resolution");
  if (!v.is_array() || v.size() != 2)
    j.fail(field, "expected [width, height] in pixels, got " + type_name(v));
  int* out[2] = {&width, &height};
  for (int c = 0; c < 2; ++c) {
    const std::string element = field + "[" + std::to_string(c) + "]";
    if (!v[c].is_number_integer())
      j.fail(element, "expected an integer, got " + type_name(v[c]) +
                          (v[c].is_number() ? " with a fraction" : ""));
    const bool in_range = v[c].is_number_unsigned() ? v[c].get<uint64_t>() <= kMaxResolution
                                                    : v[c].get<int64_t>() <= kMaxResolution;
    const int64_t x = v[c].get<int64_t>();
    if (!in_range || x < 1)
      j.fail(element,
             "must be in [1, " + std::to_string(kMaxResolution) + "] pixels, got " + v[c].dump());
    *out[c] = static_cast<int>(x);
  }
}

PinholeCamera read_camera(const JsonObject& j) {
  j.allow_only({"position", "look_at", "up", "fov_deg", "fov_axis", "resolution"});
  PinholeCamera camera;
  j.read("position", camera.position_world);
  j.read("look_at", camera.look_at_world);
  j.read("up", camera.up_world);
  j.read("fov_deg", camera.fov_deg);
  read_enum(j, "fov_axis", k_fov_axis_names, camera.fov_axis);
  if (j.has("resolution")) read_resolution(j, camera.width, camera.height);

  if (!(camera.fov_deg > 0.0f && camera.fov_deg < 180.0f))
    j.fail(j.field("fov_deg"), "must be in (0, 180) degrees, got " + fmt(camera.fov_deg));
  const V3d view = to_double(camera.look_at_world) - to_double(camera.position_world);
  if (view.length() == 0.0)
    j.fail(j.field("look_at"), "equals camera.position " + fmt(camera.position_world) +
                                   "; the camera needs a direction to look in");
  const V3d up = to_double(camera.up_world);
  if (up.length() == 0.0) j.fail(j.field("up"), "must not be the zero vector");
  if (view.normalized().cross(up.normalized()).length() < 1e-6)
    j.fail(j.field("up"),
           "is parallel to the view direction (look_at - position); choose an "
           "up vector across the view");
  return camera;
}

RenderSettings read_render(const JsonObject& j) {
  j.allow_only({"spp", "step_cells", "fiber_model", "fiber_samples", "transmittance", "shading",
                "cutoff", "seed", "light_roulette"});
  RenderSettings s;
  j.read("spp", s.spp);
  j.read("step_cells", s.step_cells);
  read_enum(j, "fiber_model", k_fiber_model_names, s.fiber_model);
  j.read("fiber_samples", s.fiber_samples);
  read_enum(j, "transmittance", k_transmittance_names, s.transmittance);
  read_enum(j, "shading", k_shading_names, s.shading);
  j.read("cutoff", s.cutoff);
  j.read("seed", s.seed);
  j.read("light_roulette", s.light_roulette);

  const std::string max_samples = std::to_string(kMaxSamples);
  if (s.spp < 1 || s.spp > kMaxSamples)
    j.fail(j.field("spp"), "must be in [1, " + max_samples + "], got " + std::to_string(s.spp));
  if (!(s.step_cells > 0.0f && s.step_cells <= 16.0f))
    j.fail(j.field("step_cells"), "must be in (0, 16] cells, got " + fmt(s.step_cells));
  if (s.fiber_samples < 1 || s.fiber_samples > kMaxSamples)
    j.fail(j.field("fiber_samples"),
           "must be in [1, " + max_samples + "], got " + std::to_string(s.fiber_samples));
  if (!(s.cutoff >= 0.0f && s.cutoff < 1.0f))
    j.fail(j.field("cutoff"), "must be in [0, 1), got " + fmt(s.cutoff));
  if (!(s.light_roulette >= 0.0f && s.light_roulette <= 1.0f))
    j.fail(j.field("light_roulette"), "must be in [0, 1], got " + fmt(s.light_roulette));
  return s;
}

ClothObject read_object(const JsonObject& j, const std::string& default_name,
                        uint64_t memory_budget_bytes) {
  j.allow_only({"name", "mesh", "cloth", "volume", "repeats_per_uv", "thickness_world",
                "extinction_per_mm", "isotropic_albedo"});
  ClothObject object;
  object.name = default_name;
  j.read("name", object.name);
  j.read("repeats_per_uv", object.repeats_per_uv);
  j.read("thickness_world", object.thickness_world);
  j.read("extinction_per_mm", object.extinction_per_mm);
  j.read("isotropic_albedo", object.isotropic_albedo);
  if (!(object.repeats_per_uv > 0.0f))
    j.fail(j.field("repeats_per_uv"), "must be greater than 0, got " + fmt(object.repeats_per_uv));
  if (!(object.thickness_world > 0.0f))
    j.fail(j.field("thickness_world"),
           "must be greater than 0, got " + fmt(object.thickness_world));
  if (!(object.extinction_per_mm >= 0.0f))
    j.fail(j.field("extinction_per_mm"), "must be >= 0, got " + fmt(object.extinction_per_mm));
  const V3f& a = object.isotropic_albedo;
  if (a.x < 0.0f || a.y < 0.0f || a.z < 0.0f || a.x > 1.0f || a.y > 1.0f || a.z > 1.0f)
    j.fail(j.field("isotropic_albedo"), "must be in [0, 1] in every channel, got " + fmt(a));

  // The cloth spec: inline, or a file (whose own errors keep its name).
  // Optional with a "volume", which replaces the texture the spec would
  // generate; the spec (or its defaults) still gives the fibre model.
  const bool has_volume = j.has("volume");
  if (!j.has("cloth") && !has_volume)
    j.fail(j.field("cloth"),
           "missing (an inline cloth spec or the path of a cloth spec file; or give a \"volume\")");
  const nlohmann::json cloth = j.has("cloth") ? j.raw("cloth") : nlohmann::json::object();
  if (cloth.is_object()) {  // without "cloth": {} (the defaults)
    object.cloth = cloth_spec_from_json(JsonObject(cloth, j.field("cloth"), j.file()));
  } else if (cloth.is_string()) {
    const fs::path cloth_path = relative_to(j.file(), cloth.get<std::string>());
    try {
      object.cloth = load_cloth_spec_file(cloth_path.string());
    } catch (const InputError& e) {
      j.fail(j.field("cloth"), e.what());
    }
  } else {
    j.fail(j.field("cloth"), "expected a cloth spec object or the path of a cloth spec file, got " +
                                 type_name(cloth));
  }

  // The volume texture, read from a VDB (its own errors keep its name and grid).
  if (has_volume) {
    std::string volume_rel;
    j.read("volume", volume_rel);
    if (volume_rel.empty()) j.fail(j.field("volume"), "is empty; expected the path of a VDB file");
    const fs::path volume_path = relative_to(j.file(), volume_rel);
    try {
      object.volume = std::make_shared<const VolumeTexture>(
          read_volume_vdb(volume_path.string(), memory_budget_bytes));
    } catch (const InputError& e) {
      j.fail(j.field("volume"), e.what());
    }
  }

  // The mesh.
  if (!j.has("mesh"))
    j.fail(j.field("mesh"), "missing (the path of an OBJ quad mesh, relative to the scene file)");
  std::string mesh_rel;
  j.read("mesh", mesh_rel);
  if (mesh_rel.empty()) j.fail(j.field("mesh"), "is empty; expected the path of an OBJ file");
  const fs::path mesh_path = relative_to(j.file(), mesh_rel);
  std::error_code ec;
  if (!fs::exists(mesh_path, ec))
    j.fail(j.field("mesh"), "mesh file not found: " + mesh_path.string());
  try {
    object.mesh = read_obj_quads(mesh_path.string());
  } catch (const InputError& e) {
    j.fail(j.field("mesh"), e.what());
  }
  return object;
}

}  // namespace

Scene load_scene(const std::string& path, uint64_t memory_budget_bytes) {
  return scene_from_text(read_text_file(path, "a JSON file"), path, memory_budget_bytes);
}

Scene scene_from_text(const std::string& text, const std::string& path,
                      uint64_t memory_budget_bytes) {
  const nlohmann::json doc = parse_json_text(text, path);
  const JsonObject top(doc, "", path);
  top.allow_only({"name", "description", "camera", "lights", "objects", "background", "render"});
  Scene scene;
  std::string label;  // name and description: checked as strings, not kept
  top.read("name", label);
  top.read("description", label);

  // Step 1: the cheap parts, so their errors come before any mesh is read.
  scene.camera = read_camera(top.object("camera"));

  if (!top.has("lights")) top.fail("lights", "missing; give at least one light");
  const nlohmann::json& lights = top.raw("lights");
  if (!lights.is_array() || lights.empty())
    top.fail("lights", "expected a non-empty array of lights, got " + type_name(lights));
  // Every march holds its lights in a fixed array; more would be dropped
  // silently by every route, so they are refused here.
  if (lights.size() > k_max_march_lights)
    top.fail("lights", "at most " + std::to_string(k_max_march_lights) + " lights, got " +
                           std::to_string(lights.size()));
  for (size_t i = 0; i < lights.size(); ++i)
    scene.lights.push_back(read_light(
        JsonObject(lights[i], "lights[" + std::to_string(i) + "]", path), LightSpelling::Scene));

  top.read("background", scene.background);
  require_non_negative(top, "background", scene.background);
  if (top.has("render")) scene.settings = read_render(top.object("render"));

  // Step 2: the cloth objects, with their cloth specs and meshes.
  if (!top.has("objects")) top.fail("objects", "missing; give at least one cloth object");
  const nlohmann::json& objects = top.raw("objects");
  if (!objects.is_array() || objects.empty())
    top.fail("objects", "expected a non-empty array of cloth objects, got " + type_name(objects));
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string field = "objects[" + std::to_string(i) + "]";
    scene.objects.push_back(
        read_object(JsonObject(objects[i], field, path), field, memory_budget_bytes));
  }

  // Step 3: checks across parts.
  if (const auto inside = camera_inside_cloth(scene))
    top.fail("camera", "position is inside the cloth volume of objects[" +
                           std::to_string(inside->object) + "] (distance " + fmt(inside->distance) +
                           " < thickness_world " + fmt(inside->thickness) + ")");
  return scene;
}

}  // namespace clothbake::io
