#pragma once
/// What a material bake would cost, measured on a probe of its real work
/// (`clothbake material --estimate`): the core's own functions timed on a few
/// light nodes, view nodes and rays, then extrapolated by counts to the whole
/// bake. As bake/baker.h's probe_bake does for the per-scene bake; the CLI
/// only prints it. Writes nothing.

#include <cstdint>

#include "core/material/material_settings.h"
#include "core/material_bake/material_source.h"

namespace clothbake {

/// The bake's four steps (material_bake.h), extrapolated, and the probe.
/// Only the bake's own seconds are estimated (what the bake's report prints
/// as "seconds"), not reading the input or writing the folder.
struct MaterialEstimate {
  int view_nodes = 0, light_nodes = 0;
  uint64_t rays = 0;  ///< view marches of the whole bake: view nodes x texels^2 x spp (x members)
  /// Addressed per crossing: crossings marched per block (settings.members
  /// where a class has as many); 1 for the whole repeat.
  double marches_per_block = 1.0;
  int probe_light_nodes = 0, probe_view_nodes = 0;
  uint64_t probe_rays = 0;         ///< marched per light-field set (twice in all)
  double probe_seconds = 0.0;      ///< wall time of the whole probe
  double fields_seconds = 0.0;     ///< step 1, extrapolated
  double marches_seconds = 0.0;    ///< step 2 (fibre tables and marches), extrapolated
  double factorise_seconds = 0.0;  ///< step 3, extrapolated
  double mips_seconds = 0.0;       ///< step 4, extrapolated from a copy of the full-rank size
  double seconds = 0.0;
  uint64_t light_field_bytes = 0;  ///< the light fields
  uint64_t fixed_bytes = 0;        ///< fields plus one view's matrix per thread
  uint64_t max_bytes = 0;          ///< the table at full rank (every view at rank = light nodes)
  /// The bake's own bytes at its high point (bake_memory.h), at the ranks
  /// expected (expected_bake_ranks); the program and its volume not counted.
  uint64_t bake_peak_bytes = 0;
  double expected_mean_rank = 0.0;
  int expected_max_rank = 0;
  /// The folder on disk, about: its images uncompressed at the expected mean
  /// rank (a view's slots above its rank are zeros, which zip all but
  /// removes) times k_disk_per_uncompressed.
  uint64_t disk_bytes = 0;
  /// For a part of a sharded bake (`--shard I/N`): the whole bake's view
  /// nodes, and the part's share of their estimated cost (material_view_cost);
  /// the figures above are then the part's.
  MaterialShard shard;
  int whole_view_nodes = 0;
  double shard_cost_share = 1.0;
};

/// What zip keeps of the folder's images at their mean rank: 0.60 on the
/// paper cloth at the defaults (112 MB on disk at mean rank 25.1). With the
/// ranks as estimated, the real drafts' folders at the defaults come to 0.76
/// to 1.16 of the estimate (docs/design/material.md, "Memory";
/// tests/cli/material_peak.sh checks a small bake).
inline constexpr double k_disk_per_uncompressed = 0.6;

/// Probe sizes: light nodes built and marched, view nodes marched, rays per
/// probe view. On the paper scene at the defaults (200 light nodes, 512 view
/// nodes) the probe takes about 2 s on 2 threads, mostly the 8 fields.
inline constexpr int k_probe_light_nodes = 8;
inline constexpr int k_probe_view_nodes = 32;
inline constexpr int k_probe_rays_per_view = 128;

/// Times the probe on the calling arena's `threads` and extrapolates:
///  - fields: P light nodes spread over the grid built, times L / P;
///  - marches: a march's cost is linear in the light nodes it serves (each
///    sample reads every node's transmittance and fibre response), so the
///    probe rays of each probe view are marched twice, with a 1-node and a
///    P-node field set, and the cost per ray is extrapolated to L nodes; the
///    fibre table (k^2 x L evaluations per view) is built for P nodes, times
///    L / P;
///  - factorisation: one Gram matrix and eigensolve of the real size, timed;
///  - mips: one level-0 table at full rank box-averaged, timed.
/// Each part's core-seconds are divided by the thread count, as the bake
/// runs its views in parallel.
/// For a part (`shard` not whole): every part builds all the light fields, so
/// those stay whole; the marches and the factorisation scale by the part's
/// share of the view cost, the rays, the table and the mips by its share of
/// the view nodes.
/// `source` and `settings` as bake_material takes them (checked by the
/// caller: check_material_bake).
MaterialEstimate probe_material(const MaterialSource& source, const MaterialSettings& settings,
                                int threads, const MaterialShard& shard = {});

}  // namespace clothbake
