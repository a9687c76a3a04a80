#include "io/light_json.h"

#include <cstdio>
#include <string>

#include <Imath/ImathVec.h>

namespace clothbake::io {

namespace {
using Imath::V3d;
using Imath::V3f;

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string fmt(const V3f& v) { return "[" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + "]"; }

/// The direction of a scene's directional light, as the unit vector toward it.
V3f scene_to_light(const JsonObject& j) {
  if (!j.has("direction"))
    j.fail(j.field("direction"), "missing (the direction the light travels, into the scene)");
  V3f direction;
  j.read("direction", direction);
  const V3d d(direction.x, direction.y, direction.z);
  const double length = d.length();
  if (!(length > 0.0))
    j.fail(j.field("direction"),
           "must not be the zero vector (it is the direction the light "
           "travels)");
  const V3d to_light = -d / length;
  return V3f(float(to_light.x), float(to_light.y), float(to_light.z));
}
}  // namespace

Light read_light(const JsonObject& j, LightSpelling spelling) {
  if (!j.has("type")) j.fail(j.field("type"), "missing; expected one of: directional, point");
  std::string type;
  j.read("type", type);
  Light light;
  const char* direction_key = spelling == LightSpelling::Scene ? "direction" : "to_light";
  if (type == "directional") {
    j.allow_only({"type", direction_key, "color", "intensity"});
    light.type = LightType::Directional;
    if (spelling == LightSpelling::Scene) {
      light.to_light_world = scene_to_light(j);
    } else {
      if (!j.has("to_light")) j.fail(j.field("to_light"), "missing (the unit vector toward it)");
      j.read("to_light", light.to_light_world);
    }
  } else if (type == "point") {
    j.allow_only({"type", "position", "color", "intensity"});
    light.type = LightType::Point;
    if (!j.has("position")) j.fail(j.field("position"), "missing (where the point light is)");
    j.read("position", light.position_world);
  } else {
    j.fail(j.field("type"),
           "unknown light type '" + type + "'; expected one of: directional, point");
  }
  j.read("color", light.color);
  j.read("intensity", light.intensity);
  if (light.color.x < 0.0f || light.color.y < 0.0f || light.color.z < 0.0f)
    j.fail(j.field("color"), "must be >= 0 in every channel, got " + fmt(light.color));
  if (light.intensity < 0.0f)
    j.fail(j.field("intensity"), "must be >= 0, got " + fmt(light.intensity));
  return light;
}

nlohmann::json stored_light_json(const Light& l) {
  auto v3 = [](const V3f& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  nlohmann::json j;
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

}  // namespace clothbake::io
