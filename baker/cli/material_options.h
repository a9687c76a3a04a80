#pragma once
// The options of `clothbake material` that set a MaterialSettings field, and
// the flag of each setting the core names in its errors (setting_flags.h).

#include <CLI/CLI.hpp>

#include "cli/setting_flags.h"
#include "core/material/material_settings.h"
#include "core/material_bake/bake_plan.h"

namespace clothbake::cli {

/// The settings' fields (material_settings.h, bake_rules.h) and the
/// command's other words the core uses ("memory": the budget, "parts",
/// "depth_scale"), with their flags.
inline constexpr SettingFlag k_material_flags[] = {{"texels", "--texels"},
                                                   {"directions", "--directions"},
                                                   {"light_directions", "--light-directions"},
                                                   {"spp", "--spp"},
                                                   {"max_error", "--max-error"},
                                                   {"field_supersample", "--field-supersample"},
                                                   {"fiber_tangent_nodes", "--fiber-tangent-nodes"},
                                                   {"address", "--address"},
                                                   {"context", "--context"},
                                                   {"members", "--members"},
                                                   {"phase_bins", "--phase-bins"},
                                                   {"shard", "--shard"},
                                                   {"parts", "--parts"},
                                                   {"depth_scale", "--depth-scale"},
                                                   {"object", "--object"},
                                                   {"memory", "--memory-gib"}};

/// What the bake chooses when the user does not (bake_plan.h): the address,
/// "auto" unless given, and the texels, whether --texels was given.
struct MaterialChoiceOptions {
  std::string address = "auto";
  CLI::Option* texels = nullptr;
};

/// Adds an option per field of `settings` to `cmd`, each checked against the
/// ranges of material_settings.h, with its default shown; --address and
/// --texels also fill `choice`.
void add_material_setting_options(CLI::App* cmd, MaterialSettings& settings,
                                  MaterialChoiceOptions& choice);

/// The request `choice` makes, after parsing (`settings` holds the texels given).
BakeRequest bake_request(const MaterialChoiceOptions& choice, const MaterialSettings& settings);

}  // namespace clothbake::cli
