#include "io/material_input.h"

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene/scene_checks.h"
#include "core/util/error.h"
#include "core/weave/thread_layout.h"
#include "io/cloth_spec_json.h"
#include "io/json_reader.h"
#include "io/scene_json.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {
/// The threads over the repeat of `spec` (its colour-free cut when the
/// parts are colour-free: what the material's texels cover).
void count_threads(const ClothSpec& spec, MaterialInput& in) {
  const WeaveDraft draft = draft_of(spec);
  in.ends = thread_layout(spec, draft, true).count();
  in.picks = thread_layout(spec, draft, false).count();
}

/// A scene's object `object` (the first when empty) into `in`.
void read_scene_input(const std::string& path, const std::string& object, PartsRequest request,
                      uint64_t budget, MaterialInput& in) {
  const MaterialParts parts =
      request == PartsRequest::Rgb ? MaterialParts::Rgb : MaterialParts::SpecularWarpWeft;
  in.scene = std::make_unique<Scene>(load_scene(path, budget));
  const Scene& scene = *in.scene;
  if (scene.objects.empty()) throw InputError("objects", "the scene has no cloth objects");
  const int o = object.empty() ? 0 : find_object(scene, object);
  if (o < 0)
    throw InputError("object", "no object named '" + object + "' (nor an index below " +
                                   std::to_string(scene.objects.size()) + ")");
  // Colour-free parts: the colour-free volume stands in for the object's own,
  // so that only one of the two volumes is ever held (colour_free_volume).
  std::vector<std::shared_ptr<const VolumeTexture>> volumes(size_t(o) + 1);
  if (parts == MaterialParts::SpecularWarpWeft)
    volumes[size_t(o)] = colour_free_volume(scene, o, budget);
  in.prepared = std::make_unique<ClothScene>(*in.scene, budget, volumes);
  in.source = material_source(*in.prepared, o, parts, budget, volumes[size_t(o)]);
  in.cloth_name = scene.objects[size_t(o)].name;
  if (in.source.parts == MaterialParts::SpecularWarpWeft)
    count_threads(in.source.cloth, in);
  else if (!scene.objects[size_t(o)].volume)
    count_threads(scene.objects[size_t(o)].cloth, in);
  if (request == PartsRequest::ColourFree && in.source.parts != parts)
    throw InputError("parts",
                     "colour-free parts are not possible for this object: " + in.source.rgb_reason);
}
}  // namespace

MaterialInput read_material_input(const std::string& path, const std::string& object,
                                  PartsRequest request, uint64_t budget) {
  MaterialInput in;
  const nlohmann::json doc = parse_json_text(read_text_file(path, "a JSON file"), path);
  try {
    if (doc.is_object() && doc.contains("objects")) {
      read_scene_input(path, object, request, budget, in);
    } else {
      const MaterialParts parts =
          request == PartsRequest::Rgb ? MaterialParts::Rgb : MaterialParts::SpecularWarpWeft;
      const ClothSpec spec = load_cloth_spec(path);
      in.source = material_source(spec, parts, budget);
      in.cloth_name = std::filesystem::path(path).stem().string();
      count_threads(parts == MaterialParts::SpecularWarpWeft ? in.source.cloth : spec, in);
    }
  } catch (const InputError& e) {
    throw e.in_file(path);
  }
  return in;
}

}  // namespace clothbake::io
