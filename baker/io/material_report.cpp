#include "io/material_report.h"

#include <algorithm>

#include "io/enum_names.h"

namespace clothbake::io {

nlohmann::json material_estimate_json(const MaterialSettings& s, const MaterialEstimate& e,
                                      int threads) {
  const nlohmann::json report = {
      {"seconds", e.seconds}, {"fields_seconds", e.fields_seconds},
      {"marches_seconds", e.marches_seconds}, {"factorise_seconds", e.factorise_seconds},
      {"mips_seconds", e.mips_seconds}, {"probe_seconds", e.probe_seconds},
      {"probe_light_nodes", e.probe_light_nodes}, {"probe_view_nodes", e.probe_view_nodes},
      {"probe_rays", e.probe_rays}, {"threads", threads}, {"view_nodes", e.view_nodes},
      {"light_nodes", e.light_nodes}, {"texels", s.texels}, {"spp", s.spp}, {"rays", e.rays},
      {"light_field_bytes", e.light_field_bytes}, {"fixed_bytes", e.fixed_bytes},
      {"max_bytes", e.max_bytes}, {"bake_peak_bytes", e.bake_peak_bytes},
      {"expected_mean_rank", e.expected_mean_rank}, {"expected_max_rank", e.expected_max_rank},
      {"bytes_on_disk", e.disk_bytes}};
  nlohmann::json part = report;
  if (s.address == MaterialAddress::Crossings) {
    part["address"] = "crossings";
    part["marches_per_block"] = e.marches_per_block;
  }
  if (e.shard.whole()) return part;
  part["shard"] = {{"part", e.shard.index + 1},
                   {"of", e.shard.count},
                   {"whole_view_nodes", e.whole_view_nodes},
                   {"cost_share", e.shard_cost_share}};
  return part;
}

nlohmann::json material_bake_report_json(const ClothMaterial& m, const MaterialBakeStats& stats,
                                        double seconds, int threads) {
  double rank_sum = 0.0, worst = 0.0;
  for (int v = 0; v < m.view_count(); ++v) {
    rank_sum += m.rank[v];
    worst = std::max(worst, double(m.error[v]));
  }
  const double core_seconds = seconds * double(threads);
  const nlohmann::json report = {
      {"seconds", seconds}, {"threads", threads}, {"view_nodes", m.view_count()},
      {"light_nodes", m.light_count()}, {"texels", m.texels()}, {"rays", stats.rays},
      {"march_samples", stats.march_samples}, {"fiber_evaluations", stats.fiber_evaluations},
      {"march_samples_per_core_second", double(stats.march_samples) / core_seconds},
      {"fiber_evaluations_per_core_second", double(stats.fiber_evaluations) / core_seconds},
      {"light_field_mib", double(stats.field_bytes) / double(1 << 20)},
      {"uncompressed_mib", stats.uncompressed_values * 2.0 / double(1 << 20)},
      {"fields_seconds", stats.fields_seconds}, {"marches_seconds", stats.marches_seconds},
      {"factorise_seconds", stats.factorise_seconds},
      {"assemble_seconds", stats.assemble_seconds},
      {"max_rank", m.max_rank}, {"mean_rank", rank_sum / double(m.view_count())},
      {"worst_view_error", worst}, {"depth_scale", m.optics.depth_scale},
      {"light_fields", enum_name(k_light_field_names, m.settings.light_fields)}};
  if (!m.addressed()) return report;
  nlohmann::json addressed = report;
  addressed["address"] = "crossings";
  addressed["blocks"] = m.crossings.count();
  addressed["crossings"] = m.crossings.ends * m.crossings.picks;
  return addressed;
}

}  // namespace clothbake::io
