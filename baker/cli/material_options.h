#pragma once
// The options of `clothbake material` that set a MaterialSettings field, and
// the flag of each setting the core names in its errors (setting_flags.h).

#include <CLI/CLI.hpp>

#include "cli/setting_flags.h"
#include "core/material/material_settings.h"

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
                                                   {"memory", "--memory"}};

/// Adds an option per field of `settings` to `cmd`, each checked against the
/// ranges of material_settings.h, with its default shown.
void add_material_setting_options(CLI::App* cmd, MaterialSettings& settings);

}  // namespace clothbake::cli
