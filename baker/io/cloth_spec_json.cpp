#include "io/cloth_spec_json.h"

#include <filesystem>

#include "core/util/error.h"
#include "io/text_file.h"
#include "io/wif_reader.h"

namespace clothbake::io {

namespace {
// A key given beside weave.wif overrides the file: one spacing, width or
// colour replaces the file's per-thread values of it.
void read_yarn(const JsonObject& j, YarnSpec& y) {
  j.allow_only({"spacing_mm", "width_mm", "thickness_mm", "color", "colors", "twist_deg",
                "ply_pitch_mm", "spacings_mm", "widths_mm"});
  if (j.has("spacing_mm")) y.spacings_mm.clear();
  if (j.has("width_mm")) y.widths_mm.clear();
  if (j.has("color")) y.colors.clear();
  j.read("spacing_mm", y.spacing_mm);
  j.read("width_mm", y.width_mm);
  j.read("thickness_mm", y.thickness_mm);
  j.read("color", y.color);
  j.read("colors", y.colors);
  j.read("twist_deg", y.twist_deg);
  j.read("ply_pitch_mm", y.ply_pitch_mm);
  j.read("spacings_mm", y.spacings_mm);
  j.read("widths_mm", y.widths_mm);
}

nlohmann::json yarn_json(const YarnSpec& y) {
  auto v3 = [](const Imath::V3f& c) { return nlohmann::json::array({c.x, c.y, c.z}); };
  nlohmann::json j = {{"spacing_mm", y.spacing_mm},     {"width_mm", y.width_mm},
                      {"thickness_mm", y.thickness_mm}, {"color", v3(y.color)},
                      {"twist_deg", y.twist_deg},       {"ply_pitch_mm", y.ply_pitch_mm}};
  if (!y.colors.empty()) {
    j["colors"] = nlohmann::json::array();
    for (const Imath::V3f& c : y.colors) j["colors"].push_back(v3(c));
  }
  if (!y.spacings_mm.empty()) j["spacings_mm"] = y.spacings_mm;
  if (!y.widths_mm.empty()) j["widths_mm"] = y.widths_mm;
  return j;
}
}  // namespace

nlohmann::json cloth_spec_json(const ClothSpec& s) {
  nlohmann::json j;
  if (s.draft.empty()) j["weave"] = {{"pattern", s.pattern}};
  else j["weave"] = {{"draft", s.draft}};
  j["warp"] = yarn_json(s.warp);
  j["weft"] = yarn_json(s.weft);
  j["crimp"] = s.crimp;
  j["angle_spread_deg"] = s.angle_spread_deg;
  const DensitySpec& d = s.density;
  j["density"] = {{"core", d.core},
                  {"edge", d.edge},
                  {"falloff", d.falloff},
                  {"top_factor", d.top_factor},
                  {"noise_amplitude", d.noise_amplitude},
                  {"noise_scale_mm", d.noise_scale_mm}};
  const ShadingSpec& h = s.shading;
  j["shading"] = {{"specular_top", h.specular_top},     {"specular_bottom", h.specular_bottom},
                  {"diffuse_top", h.diffuse_top},       {"diffuse_bottom", h.diffuse_bottom},
                  {"exponent", h.exponent},             {"variation", h.variation},
                  {"fiber_aspect", h.fiber_aspect}};
  const ResolutionSpec& r = s.resolution;
  j["resolution"] = {{"cells_x", r.cells_x},
                     {"cells_y", r.cells_y},
                     {"cells_per_thread", r.cells_per_thread},
                     {"layers", r.layers},
                     {"supersample", r.supersample}};
  j["seed"] = s.seed;
  return j;
}

ClothSpec cloth_spec_from_json(const JsonObject& j) {
  ClothSpec s;
  j.allow_only({"name", "description", "weave", "warp", "weft", "crimp", "angle_spread_deg",
                "density", "shading", "resolution", "seed"});
  if (j.has("weave")) {
    const JsonObject w = j.object("weave");
    w.allow_only({"pattern", "draft", "wif", "rising_shed"});
    if (w.has("rising_shed") && !w.has("wif"))
      w.fail(w.field("rising_shed"), "only with weave.wif (it says how to read the file's lifts)");
    if (int(w.has("pattern")) + int(w.has("draft")) + int(w.has("wif")) > 1)
      w.fail(w.path().empty() ? "weave" : w.path(), "give one of pattern, draft or wif");
    w.read("pattern", s.pattern);
    w.read("draft", s.draft);
    if (w.has("draft") && s.draft.empty()) w.fail(w.field("draft"), "the draft is empty");
    if (w.has("wif")) {
      // The file first: every other key of the spec is read over it.
      std::string rel;
      w.read("wif", rel);
      if (rel.empty()) w.fail(w.field("wif"), "the path is empty");
      std::filesystem::path full(rel);
      if (full.is_relative()) full = std::filesystem::path(j.file()).parent_path() / full;
      WifFile wif = read_wif_file(full.string());
      if (w.has("rising_shed")) {
        const auto& v = w.raw("rising_shed");
        if (!v.is_boolean())
          w.fail(w.field("rising_shed"), "expected true or false, got " + json_type_name(v));
        wif.loom.rising_shed = v.get<bool>();  // overrides the file's Rising Shed
      }
      s = apply_wif(wif, s);
    }
  }
  if (j.has("warp")) read_yarn(j.object("warp"), s.warp);
  if (j.has("weft")) read_yarn(j.object("weft"), s.weft);
  j.read("crimp", s.crimp);
  j.read("angle_spread_deg", s.angle_spread_deg);
  if (j.has("density")) {
    const JsonObject d = j.object("density");
    d.allow_only({"core", "edge", "falloff", "top_factor", "noise_amplitude", "noise_scale_mm"});
    d.read("core", s.density.core);
    d.read("edge", s.density.edge);
    d.read("falloff", s.density.falloff);
    d.read("top_factor", s.density.top_factor);
    d.read("noise_amplitude", s.density.noise_amplitude);
    d.read("noise_scale_mm", s.density.noise_scale_mm);
  }
  if (j.has("shading")) {
    const JsonObject h = j.object("shading");
    h.allow_only({"specular_top", "specular_bottom", "diffuse_top", "diffuse_bottom", "exponent",
                  "variation", "fiber_aspect"});
    h.read("specular_top", s.shading.specular_top);
    h.read("specular_bottom", s.shading.specular_bottom);
    h.read("diffuse_top", s.shading.diffuse_top);
    h.read("diffuse_bottom", s.shading.diffuse_bottom);
    h.read("exponent", s.shading.exponent);
    h.read("variation", s.shading.variation);
    h.read("fiber_aspect", s.shading.fiber_aspect);
  }
  if (j.has("resolution")) {
    const JsonObject r = j.object("resolution");
    r.allow_only({"cells_x", "cells_y", "cells_per_thread", "layers", "supersample"});
    r.read("cells_x", s.resolution.cells_x);
    r.read("cells_y", s.resolution.cells_y);
    r.read("cells_per_thread", s.resolution.cells_per_thread);
    r.read("layers", s.resolution.layers);
    r.read("supersample", s.resolution.supersample);
  }
  j.read("seed", s.seed);
  try {
    validate(s);
  } catch (const InputError& e) {
    // The core names fields relative to the spec; prefix where the spec sits.
    const std::string prefix = j.path().empty() ? "" : j.path() + ".";
    throw InputError(prefix + e.field(), e.message(), j.file());
  }
  return s;
}

ClothSpec cloth_spec_from_wif(const WifFile& wif) {
  ClothSpec s = apply_wif(wif, ClothSpec{});
  try {
    validate(s);
  } catch (const InputError& e) {
    throw InputError(e.field(), e.message() + " (as the WIF file's [WARP] / [WEFT] sizes give it)",
                     wif.path);
  }
  return s;
}

ClothSpec cloth_spec_from_text(const std::string& text, const std::string& path) {
  if (is_wif_path(path)) return cloth_spec_from_wif(parse_wif(text, path));
  const nlohmann::json doc = parse_json_text(text, path);
  const JsonObject top(doc, "", path);
  if (!top.has("objects")) return cloth_spec_from_json(top);

  // A scene: the first object's cloth, inline or by file.
  const auto& objects = top.raw("objects");
  if (!objects.is_array() || objects.empty())
    top.fail("objects", "expected a non-empty array of cloth objects");
  const JsonObject first(objects[0], "objects[0]", path);
  if (!first.has("cloth"))
    first.fail("objects[0].cloth",
               first.has("volume") ? "missing; this object's texture is read from its \"volume\" "
                                     "VDB, there is no cloth spec to generate from"
                                   : "missing");
  const auto& cloth = first.raw("cloth");
  if (cloth.is_string()) {
    const std::filesystem::path rel = cloth.get<std::string>();
    const std::filesystem::path full =
        rel.is_absolute() ? rel : std::filesystem::path(path).parent_path() / rel;
    return load_cloth_spec_file(full.string());
  }
  return cloth_spec_from_json(JsonObject(cloth, "objects[0].cloth", path));
}

ClothSpec load_cloth_spec(const std::string& path) {
  return cloth_spec_from_text(
      read_text_file(path, is_wif_path(path) ? "a WIF file" : "a JSON file"), path);
}

ClothSpec load_cloth_spec_file(const std::string& path) {
  if (is_wif_path(path)) return cloth_spec_from_wif(read_wif_file(path));
  const nlohmann::json doc = read_json_file(path);
  return cloth_spec_from_json(JsonObject(doc, "", path));
}

}  // namespace clothbake::io
