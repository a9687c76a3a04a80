#include "io/light_json.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <Imath/ImathVec.h>

namespace clothbake::io {

namespace {
using Imath::V3d;
using Imath::V3f;

constexpr const char* k_types = "directional, point, spot, area";

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string fmt(const V3f& v) { return "[" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + "]"; }

V3f to_float(const V3d& v) { return V3f(float(v.x), float(v.y), float(v.z)); }
V3d to_double(const V3f& v) { return V3d(v.x, v.y, v.z); }

/// A required direction of any non-zero length, normalised (in double, so
/// the stored float is the rounded unit vector).
V3d unit_vector(const JsonObject& j, const char* key, const char* meaning,
                const char* zero_meaning = nullptr) {
  if (!j.has(key)) j.fail(j.field(key), std::string("missing (") + meaning + ")");
  V3f v;
  j.read(key, v);
  const V3d d = to_double(v);
  const double length = d.length();
  if (!(length > 0.0))
    j.fail(j.field(key), std::string("must not be the zero vector (") +
                             (zero_meaning ? zero_meaning : meaning) + ")");
  if (!std::isfinite(length))
    j.fail(j.field(key), std::string("must be finite (") + meaning + ")");
  return d / length;
}

V3f required_position(const JsonObject& j, const char* what) {
  if (!j.has("position")) j.fail(j.field("position"), std::string("missing (") + what + ")");
  V3f p;
  j.read("position", p);
  return p;
}

float positive(const JsonObject& j, const char* key, const nlohmann::json& value, float v) {
  if (!(v > 0.0f) || !std::isfinite(v))
    j.fail(j.field(key), "must be > 0 and finite, got " + value.dump());
  return v;
}

/// A spot light's cone, spelled as Blender's Size (full angle, degrees) and Blend.
void read_spot_cone(const JsonObject& j, Light& light) {
  float size_deg = 45.0f, blend = 0.15f;
  j.read("spot_size_deg", size_deg);
  j.read("spot_blend", blend);
  if (!(size_deg > 0.0f && size_deg <= 180.0f))
    j.fail(j.field("spot_size_deg"), "must be in (0, 180] degrees (the full cone angle), got " +
                                         fmt(size_deg));
  if (!(blend >= 0.0f && blend <= 1.0f))
    j.fail(j.field("spot_blend"), "must be in [0, 1], got " + fmt(blend));
  const double half = 0.5 * double(size_deg) * std::numbers::pi / 180.0;
  light.spot_cos_half_angle = float(std::cos(half));
  light.spot_smooth = float((1.0 - std::cos(half)) * double(blend));
  j.read("axis_cosine", light.spot_axis_cosine);
}

/// An area light's shape and sides: `size` is one length for a square or a
/// disk, [width, height] for a rectangle or an ellipse.
void read_area_shape(const JsonObject& j, Light& light) {
  std::string shape = "rectangle";
  j.read("shape", shape);
  const bool single = shape == "square" || shape == "disk";
  if (!single && shape != "rectangle" && shape != "ellipse")
    j.fail(j.field("shape"), "unknown shape '" + shape +
                                 "'; expected one of: rectangle, square, disk, ellipse");
  light.area_shape = shape == "disk" || shape == "ellipse" ? AreaShape::Ellipse
                                                            : AreaShape::Rectangle;
  if (!j.has("size"))
    j.fail(j.field("size"), single ? "missing (the side or diameter, world units)"
                                   : "missing ([width, height], world units)");
  const nlohmann::json& size = j.raw("size");
  if (single) {
    if (!size.is_number())
      j.fail(j.field("size"), "must be a number for a " + shape + " (one side), got " +
                                  json_type_name(size));
    light.area_width = light.area_height = positive(j, "size", size, size.get<float>());
  } else {
    if (!size.is_array() || size.size() != 2 || !size[0].is_number() || !size[1].is_number())
      j.fail(j.field("size"), "must be [width, height] for a " + shape + ", got " + size.dump());
    light.area_width = positive(j, "size", size, size[0].get<float>());
    light.area_height = positive(j, "size", size, size[1].get<float>());
  }
}

/// The area light's first side, made orthogonal to its normal (Gram-Schmidt).
V3d side_axis(const JsonObject& j, const V3d& normal) {
  const V3d x = unit_vector(j, "x_axis", "the direction of the light's first side");
  const V3d side = x - normal * x.dot(normal);
  if (!(side.length() > 1e-6))
    j.fail(j.field("x_axis"), "is parallel to the direction; it must lie in the light's plane");
  return side / side.length();
}

V3f stored_unit(const JsonObject& j, const char* key) {
  if (!j.has(key)) j.fail(j.field(key), "missing");
  V3f v;
  j.read(key, v);
  return v;
}
}  // namespace

Light read_light(const JsonObject& j, LightSpelling spelling) {
  if (!j.has("type")) j.fail(j.field("type"), std::string("missing; expected one of: ") + k_types);
  std::string type;
  j.read("type", type);
  Light light;
  const bool scene = spelling == LightSpelling::Scene;
  if (type == "directional") {
    j.allow_only({"type", scene ? "direction" : "to_light", "color", "intensity"});
    light.type = LightType::Directional;
    if (scene) {
      light.to_light_world = to_float(
          -unit_vector(j, "direction", "the direction the light travels, into the scene",
                       "it is the direction the light travels"));
    } else {
      if (!j.has("to_light")) j.fail(j.field("to_light"), "missing (the unit vector toward it)");
      j.read("to_light", light.to_light_world);
    }
  } else if (type == "point") {
    j.allow_only({"type", "position", "color", "intensity"});
    light.type = LightType::Point;
    light.position_world = required_position(j, "where the point light is");
  } else if (type == "spot") {
    light.type = LightType::Spot;
    light.position_world = required_position(j, "where the spot light is");
    if (scene) {
      j.allow_only({"type", "position", "direction", "spot_size_deg", "spot_blend",
                    "axis_cosine", "color", "intensity"});
      light.axis_world = to_float(unit_vector(j, "direction", "the cone's axis, the way it shines"));
      read_spot_cone(j, light);
    } else {
      j.allow_only({"type", "position", "axis", "cos_half_angle", "smooth", "axis_cosine",
                    "color", "intensity"});
      light.axis_world = stored_unit(j, "axis");
      j.read("cos_half_angle", light.spot_cos_half_angle);
      j.read("smooth", light.spot_smooth);
      j.read("axis_cosine", light.spot_axis_cosine);
    }
  } else if (type == "area") {
    light.type = LightType::Area;
    light.position_world = required_position(j, "the centre of the area light");
    if (scene) {
      j.allow_only({"type", "position", "direction", "x_axis", "shape", "size", "color",
                    "intensity"});
      const V3d normal = unit_vector(j, "direction", "the way the light shines, its normal");
      light.axis_world = to_float(normal);
      light.side_world = to_float(side_axis(j, normal));
      read_area_shape(j, light);
    } else {
      j.allow_only({"type", "position", "axis", "side", "shape", "width", "height", "color",
                    "intensity"});
      light.axis_world = stored_unit(j, "axis");
      light.side_world = stored_unit(j, "side");
      std::string shape;
      j.read("shape", shape);
      light.area_shape = shape == "ellipse" ? AreaShape::Ellipse : AreaShape::Rectangle;
      j.read("width", light.area_width);
      j.read("height", light.area_height);
    }
  } else {
    j.fail(j.field("type"),
           "unknown light type '" + type + "'; expected one of: " + k_types);
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
  switch (l.type) {
    case LightType::Directional:
      j["type"] = "directional";
      j["to_light"] = v3(l.to_light_world);
      break;
    case LightType::Point:
      j["type"] = "point";
      j["position"] = v3(l.position_world);
      break;
    case LightType::Spot:
      j["type"] = "spot";
      j["position"] = v3(l.position_world);
      j["axis"] = v3(l.axis_world);
      j["cos_half_angle"] = l.spot_cos_half_angle;
      j["smooth"] = l.spot_smooth;
      if (!l.spot_axis_cosine) j["axis_cosine"] = false;  // written only off its default
      break;
    case LightType::Area:
      j["type"] = "area";
      j["position"] = v3(l.position_world);
      j["axis"] = v3(l.axis_world);
      j["side"] = v3(l.side_world);
      j["shape"] = l.area_shape == AreaShape::Ellipse ? "ellipse" : "rectangle";
      j["width"] = l.area_width;
      j["height"] = l.area_height;
      break;
  }
  j["color"] = v3(l.color);
  j["intensity"] = l.intensity;
  return j;
}

}  // namespace clothbake::io
