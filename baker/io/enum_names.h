#pragma once
/// How the files spell the core's enums, stated once: a scene's render block,
/// a material's manifest and the command line read and write them here.

#include <array>
#include <string>
#include <utility>

#include "core/fiber/fiber_model.h"
#include "core/geometry/direction_grid.h"
#include "core/march/march_settings.h"
#include "core/material/material_settings.h"
#include "io/json_reader.h"

namespace clothbake::io {

/// A table of spellings: the first name given for a value is the one written.
template <typename E, std::size_t N>
using EnumNames = std::array<std::pair<const char*, E>, N>;

inline constexpr std::array<std::pair<const char*, FiberModelKind>, 3> k_fiber_model_names{{
    {"ellipsoid", FiberModelKind::Ellipsoid},
    {"table", FiberModelKind::Table},
    {"kajiya-kay", FiberModelKind::KajiyaKay},
}};
inline constexpr std::array<std::pair<const char*, ShadingMode>, 2> k_shading_names{{
    {"fiber", ShadingMode::Fiber},
    {"isotropic", ShadingMode::Isotropic},
}};
inline constexpr std::array<std::pair<const char*, TransmittanceMode>, 2> k_transmittance_names{{
    {"shadow-march", TransmittanceMode::ShadowMarch},
    {"cached", TransmittanceMode::Cached},
}};
/// A material's light-node layout as its manifest spells it.
inline constexpr std::array<std::pair<const char*, DirectionMap>, 2> k_light_map_names{{
    {"hemi-octahedral-horizon", DirectionMap::HemiOctahedralHorizon},
    {"hemi-octahedral", DirectionMap::HemiOctahedral},
}};
/// The same layouts as `clothbake material --light-map` spells them (short,
/// for typing), in the same order.
inline constexpr std::array<std::pair<const char*, MaterialParts>, 2> k_material_parts_names{{
    {"rgb", MaterialParts::Rgb},
    {"specular-warp-weft", MaterialParts::SpecularWarpWeft},
}};
/// A material's texels: over the whole repeat, or one block per crossing class.
inline constexpr std::array<std::pair<const char*, MaterialAddress>, 2> k_material_address_names{{
    {"repeat", MaterialAddress::Repeat},
    {"crossings", MaterialAddress::Crossings},
}};
/// What makes two crossings one class of an addressed material.
inline constexpr std::array<std::pair<const char*, CrossingStencil>, 2> k_crossing_stencil_names{{
    {"plus-1", CrossingStencil::Plus1},
    {"3x3", CrossingStencil::Square1},
}};
/// How a material's light fields are read (core/material_bake/light_fields.h), in
/// its manifest and on `clothbake material --light-fields`.
inline constexpr std::array<std::pair<const char*, LightFieldMethod>, 3> k_light_field_names{{
    {"auto", LightFieldMethod::Auto},
    {"interpolated", LightFieldMethod::Interpolated},
    {"layer-march", LightFieldMethod::LayerMarch},
}};
inline constexpr std::array<std::pair<const char*, DirectionMap>, 2> k_light_map_flags{{
    {"horizon", DirectionMap::HemiOctahedralHorizon},
    {"square", DirectionMap::HemiOctahedral},
}};

/// The spelling of `value` (the first name given for it).
template <typename E, std::size_t N>
const char* enum_name(const EnumNames<E, N>& names, E value) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "";
}

/// "a, b, c": the spellings, for messages and CLI11's IsMember.
template <typename E, std::size_t N>
std::string enum_list(const EnumNames<E, N>& names) {
  std::string list;
  for (const auto& [name, v] : names) list += std::string(list.empty() ? "" : ", ") + name;
  return list;
}

/// True and `out` set when `text` is one of the spellings.
template <typename E, std::size_t N>
bool parse_enum(const EnumNames<E, N>& names, const std::string& text, E& out) {
  for (const auto& [name, v] : names)
    if (text == name) {
      out = v;
      return true;
    }
  return false;
}

/// Reads the string `key` of `j` (when present) as one of `names`; any other
/// value fails naming the field and the spellings it may take.
template <typename E, std::size_t N>
void read_enum(const JsonObject& j, const char* key, const EnumNames<E, N>& names, E& out) {
  if (!j.has(key)) return;
  std::string s;
  j.read(key, s);
  if (!parse_enum(names, s, out))
    j.fail(j.field(key), "unknown value '" + s + "'; expected one of: " + enum_list(names));
}

}  // namespace clothbake::io
