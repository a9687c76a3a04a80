#include "cli/material_options.h"

#include <cstdlib>
#include <map>
#include <string>

#include "cli/option_range.h"
#include "io/enum_names.h"

namespace clothbake::cli {

namespace {
/// An option whose value is one of an enum's spellings (io/enum_names.h),
/// checked by CLI11 and shown with its default's spelling.
template <typename E, std::size_t N>
CLI::Option* add_enum_option(CLI::App* cmd, const std::string& flag, E& value,
                             const io::EnumNames<E, N>& names, const std::string& help) {
  std::map<std::string, E> map;
  for (const auto& [name, v] : names) map[name] = v;
  return cmd->add_option(flag, value, help)
      ->transform(CLI::CheckedTransformer(map))
      ->default_str(io::enum_name(names, value));
}
/// The settings a user chooses: how fine, how many directions, how exact, and
/// what the texels cover.
void add_everyday_options(CLI::App* cmd, MaterialSettings& s, MaterialChoiceOptions& choice) {
  // The checks of material_settings.h that a range cannot state.
  const CLI::Validator power_of_two(
      [](std::string& v) {
        const int n = std::atoi(v.c_str());
        return n > 0 && (n & (n - 1)) == 0
                   ? std::string()
                   : "must be a power of 2 (the mip levels halve it down to 1), got " + v;
      },
      "POWER OF 2");
  choice.texels =
      cmd->add_option("--texels", s.texels,
                      "R: texels per repeat side (per crossing side when addressed per "
                      "crossing), a power of 2; default: 32 for the whole repeat, " +
                          std::to_string(k_auto_crossing_texels) + " per crossing")
          ->check(in_range(k_min_material_texels, k_max_material_texels) & power_of_two);
  cmd->add_option("--directions", s.directions, "K: view nodes per side of each hemisphere")
      ->check(in_range(k_min_material_directions, k_max_material_directions))
      ->capture_default_str();
  cmd->add_option("--light-directions", s.light_directions,
                  "KL: light nodes per side of each hemisphere")
      ->check(in_range(k_min_material_directions, k_max_material_directions))
      ->capture_default_str();
  cmd->add_option("--spp", s.spp, "samples per texel and view node")
      ->check(in_range(k_min_material_spp, k_max_material_spp))
      ->capture_default_str();
  cmd->add_option("--max-error", s.max_error,
                  "per view node: relative RMSE the factorisation may leave (0 = exact)")
      ->check(in_range(k_min_material_error, k_max_material_error))
      ->capture_default_str();
  cmd->add_option("--address", choice.address,
                  "what the texels cover: the whole repeat (--texels per repeat side), or one "
                  "block per distinct crossing neighbourhood, addressed per crossing (--texels "
                  "per crossing side): its size follows the weave's variety, not its repeat; "
                  "auto: the whole repeat where it leaves 2 texels a thread and fits --memory-gib, "
                  "else per crossing")
      ->check(CLI::IsMember({"auto", "repeat", "crossings"}))
      ->capture_default_str();
}

/// Knobs of the bake's numerics, each with a measured default: touched to
/// study a limit (docs/design/material.md), not to make a bake fit.
void add_expert_options(CLI::App* cmd, MaterialSettings& s) {
  const CLI::Validator tangent_nodes(
      [](std::string& v) {
        const int n = std::atoi(v.c_str());
        return n == 0 || (n >= k_min_fiber_tangent_nodes && n <= k_max_fiber_tangent_nodes)
                   ? std::string()
                   : "must be 0 or in [" + std::to_string(k_min_fiber_tangent_nodes) + ", " +
                         std::to_string(k_max_fiber_tangent_nodes) + "], got " + v;
      },
      "0 OR RANGE");
  cmd->add_option("--field-supersample", s.field_supersample, "light-field points per cell edge")
      ->check(in_range(k_min_field_supersample, k_max_field_supersample))
      ->capture_default_str();
  add_enum_option(cmd, "--light-map", s.light_map, io::k_light_map_flags,
                  "light nodes: drawn toward the horizon, or the plain hemi-octahedral square");
  add_enum_option(cmd, "--light-fields", s.light_fields, io::k_light_field_names,
                  "how the bake reads light toward each sample: interpolated between the "
                  "cells' centres, or marched through the sample's own layer (right where "
                  "cells are opaque, about 6 x the march's time); auto: layer-march when "
                  "sigma x the densest cell's rho x a field cell's edge exceeds 1");
  cmd->add_flag("--view-parallax,!--no-view-parallax", s.view_parallax,
                "read each view node where its ray meets the eye's at a depth fitted to the "
                "material (sharper weave between view nodes of a thick cloth)")
      ->capture_default_str();
  cmd->add_option("--context", s.context,
                  "--address crossings: crossings either side of a block's that its light "
                  "fields span")
      ->check(in_range(k_min_material_context, k_max_material_context))
      ->capture_default_str();
  add_enum_option(cmd, "--stencil", s.stencil, io::k_crossing_stencil_names,
                  "--address crossings: what makes two crossings one block: their plus-1 "
                  "stencil, or their 3 x 3 window (about 3 x the blocks; the neighbouring "
                  "threads' crossings, which grazing rays see)");
  cmd->add_option("--members", s.members,
                  "--address crossings: crossings of each class a block averages, spread over "
                  "the class (1: its first crossing alone; more average the crossings' own "
                  "randomness, at that many times the bake)")
      ->check(in_range(k_min_material_members, k_max_material_members))
      ->capture_default_str();
  cmd->add_option("--phase-bins", s.phase_bins,
                  "--address crossings: bins of the ply phase of the yarn on top at a "
                  "crossing, each its own block (about that many times the blocks): the "
                  "generator's per-yarn random phase, which shows per pixel at a thread per "
                  "pixel or two; 1: not in the classes")
      ->check(in_range(k_min_phase_bins, k_max_phase_bins))
      ->capture_default_str();
  cmd->add_option("--fiber-tangent-nodes", s.fiber_tangent_nodes,
                  "fibre response tabulated over N x N tangents per view node (0: exact per cell)")
      ->check(tangent_nodes)
      ->capture_default_str();
}
}  // namespace

BakeRequest bake_request(const MaterialChoiceOptions& choice, const MaterialSettings& settings) {
  BakeRequest r;
  MaterialAddress address = MaterialAddress::Repeat;
  if (io::parse_enum(io::k_material_address_names, choice.address, address)) r.address = address;
  if (choice.texels != nullptr && choice.texels->count() > 0) r.texels = settings.texels;
  return r;
}

void add_material_setting_options(CLI::App* cmd, MaterialSettings& s,
                                  MaterialChoiceOptions& choice) {
  add_everyday_options(cmd, s, choice);
  add_expert_options(
      cmd->add_option_group(
          "Expert", "the bake's numerics; their defaults are measured (docs/design/material.md)"),
      s);
}

}  // namespace clothbake::cli
