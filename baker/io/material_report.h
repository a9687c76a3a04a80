#pragma once
/// What `clothbake material` prints: the bake's report (one JSON line: time,
/// counts, speeds, ranks) and --estimate's (the probe's extrapolation).

#include <nlohmann/json.hpp>

#include "core/material/cloth_material.h"
#include "core/material_bake/material_bake.h"
#include "core/material_bake/material_probe.h"

namespace clothbake::io {

nlohmann::json material_estimate_json(const MaterialSettings& settings,
                                      const MaterialEstimate& estimate, int threads);

nlohmann::json material_bake_report_json(const ClothMaterial& material,
                                         const MaterialBakeStats& stats, double seconds,
                                         int threads);

}  // namespace clothbake::io
