#include "core/material_bake/material_bake.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include "core/material_bake/bake_rules.h"
#include "core/material_bake/factorisation.h"
#include "core/material_bake/material_sample.h"
#include "core/material_bake/material_shard.h"
#include "core/material_bake/parallax_fit.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"

namespace clothbake {

namespace {
using Imath::V3f;
}  // namespace

bool tabulates_fiber(const MaterialSettings& settings, const MaterialOptics& optics) {
  return settings.fiber_tangent_nodes > 0 && optics.shading == ShadingMode::Fiber;
}

ClothMaterial unbaked_material(const VolumeTexture& volume, const MaterialOptics& optics,
                               const MaterialSettings& settings) {
  ClothMaterial m;
  m.settings = settings;
  m.optics = optics;
  m.cloth_hash = volume.content_hash();
  m.repeat_mm = volume.size_mm();
  m.view_grid.k = settings.directions;
  m.light_grid.k = settings.light_directions;
  m.light_grid.map = settings.light_map;
  // Auto is settled here, once, from the cloth: every field, estimate and
  // manifest reads the method the bake used.
  m.settings.light_fields = LightFieldSet::resolve(
      settings.light_fields, volume, optics.extinction_per_mm, settings.field_supersample);
  return m;
}

ClothMaterial unbaked_material(const MaterialSource& source, const MaterialSettings& settings) {
  ClothMaterial m = unbaked_material(*source.volume, source.optics, settings);
  if (m.colour_parts()) {
    m.set_cloth(source.cloth, source.palette);
    m.written_repeats = source.written_repeats;
  }
  return m;
}

uint64_t material_field_bytes(const ClothMaterial& material, const VolumeTexture& volume) {
  const MaterialLayout layout = material.layout();
  const int s = material.settings.field_supersample;
  const LightFieldMethod method = material.settings.light_fields;
  if (!material.addressed())
    return LightFieldSet::bytes_for(volume, layout.light_count(), s, method);
  // One window's fields at a time.
  uint64_t fields = 0;
  for (const BlockWindow& b : block_windows(material, volume))
    fields = std::max<uint64_t>(
        fields, LightFieldSet::bytes_for_window(volume, b.cells_x, b.cells_y, layout.light_count(),
                                                s, method));
  return fields;
}

uint64_t material_bake_fixed_bytes(const ClothMaterial& material, const VolumeTexture& volume,
                                   int threads) {
  const MaterialLayout layout = material.layout();
  const MaterialSettings& s = material.settings;
  const uint64_t fields = material_field_bytes(material, volume);
  if (!material.addressed())
    return fields + uint64_t(std::max(threads, 1)) * layout.view_matrix_bytes();
  // Every view node's matrix (level 0 by the light nodes) and fibre table,
  // held across the blocks.
  const uint64_t k = tabulates_fiber(s, material.optics) ? uint64_t(s.fiber_tangent_nodes) : 0;
  return fields +
         uint64_t(layout.view_count()) *
             (layout.level_texels(0) * (uint64_t(layout.channels) * layout.light_count() + 1) +
              k * k * layout.light_count() * 2) *
             sizeof(float);
}

namespace {
/// Per thread: the view node's fibre table and the march's work space.
struct ViewLocal {
  FiberLightTable fiber_table;
  NodeMarchScratch scratch;
  NodeMarchCounts counts;
  std::vector<V3f> radiance, radiance_next;
};

/// Step 2 for one view node, rows [y0, y1) of level 0: every texel's spp
/// jittered samples marched for all light nodes under `fields`, averaged
/// into the texels x channels by light-node matrix `m` (its rows from
/// texel y0 R on) and each texel's alpha (into `alpha`, indexed from 0).
/// `table`: the view node's fibre table, or null.
void march_view_rows(const ClothMaterial& material, const VolumeTexture& volume,
                     const FiberShader& shader, const LightFieldSet& fields,
                     std::span<const V3f> light_local, int view, int y0, int y1,
                     const FiberLightTable* table, ViewLocal& local, Eigen::MatrixXf& m,
                     std::vector<float>& alpha, const CrossingClasses::Crossing* at = nullptr,
                     float weight = 1.0f) {
  const MaterialSettings& settings = material.settings;
  const int R = settings.texels, n_lights = int(light_local.size());
  local.scratch.view_tag = uint32_t(view) + 1;
  const int ch = material.layout().channels;
  const bool parts = material.colour_parts();
  local.radiance.resize(size_t(n_lights));
  local.radiance_next.resize(size_t(n_lights));
  const float inv_spp = 1.0f / float(settings.spp);
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < R; ++x) {
      std::fill(local.radiance.begin(), local.radiance.end(), V3f(0.0f));
      std::fill(local.radiance_next.begin(), local.radiance_next.end(), V3f(0.0f));
      float see_through = 0.0f;
      for (int k = 0; k < settings.spp; ++k) {
        NodeMarchInput in =
            at ? material_sample(material, volume, shader, fields, light_local, view, x, y, k, *at)
               : material_sample(material, volume, shader, fields, light_local, view, x, y, k);
        in.fiber_table = table;
        see_through += in.length_mm > 0.0f
                           ? march_view_ray_all_lights(in, local.radiance.data(), local.scratch,
                                                       local.counts, local.radiance_next.data())
                           : 1.0f;
      }
      const Eigen::Index row = (Eigen::Index(y) * R + x) * ch;
      if (weight == 1.0f) {
        for (int n = 0; n < n_lights; ++n) {
          const V3f r = local.radiance[size_t(n)] * inv_spp;
          if (!parts) {
            m(row, n) = r.x, m(row + 1, n) = r.y, m(row + 2, n) = r.z;
            continue;
          }
          // Specular has no colour: the next threads' joins the own.
          const V3f rn = local.radiance_next[size_t(n)] * inv_spp;
          m(row, n) = r.x + rn.x, m(row + 1, n) = r.y, m(row + 2, n) = r.z;
          m(row + 3, n) = rn.y, m(row + 4, n) = rn.z;
        }
        alpha[size_t(y) * R + x] = 1.0f - see_through * inv_spp;
        continue;
      }
      // One of several member crossings (colour-free parts): its share.
      const float w = weight * inv_spp;
      for (int n = 0; n < n_lights; ++n) {
        const V3f r = local.radiance[size_t(n)] * w, rn = local.radiance_next[size_t(n)] * w;
        m(row, n) += r.x + rn.x, m(row + 1, n) += r.y, m(row + 2, n) += r.z;
        m(row + 3, n) += rn.y, m(row + 4, n) += rn.z;
      }
      alpha[size_t(y) * R + x] += weight * (1.0f - see_through * inv_spp);
    }
}

/// The view node's fibre table (tabulates_fiber), counted.
void build_fiber_table(const ClothMaterial& material, const FiberShader& shader,
                       std::span<const V3f> light_local, int view, FiberLightTable& table,
                       NodeMarchCounts& counts) {
  const int k = material.settings.fiber_tangent_nodes;
  table.build(shader, light_local,
              material.local_from_material(material.view_grid.bake_direction(view)), k);
  counts.fiber_evaluations += uint64_t(k) * uint64_t(k) * uint64_t(light_local.size());
}

/// Step 2 for one view node over the whole repeat: the matrix (returned)
/// and the alpha (into `f`).
Eigen::MatrixXf march_view_node(const ClothMaterial& material, const VolumeTexture& volume,
                                const FiberShader& shader, const LightFieldSet& fields,
                                std::span<const V3f> light_local, int view, ViewLocal& local,
                                ViewFactors& f) {
  const int R = material.settings.texels;
  const bool tabulate = tabulates_fiber(material.settings, material.optics);
  if (tabulate)
    build_fiber_table(material, shader, light_local, view, local.fiber_table, local.counts);
  Eigen::MatrixXf m(Eigen::Index(R) * R * material.layout().channels,
                    Eigen::Index(light_local.size()));
  f.alpha.assign(size_t(R) * R, 0.0f);
  march_view_rows(material, volume, shader, fields, light_local, view, 0, R,
                  tabulate ? &local.fiber_table : nullptr, local, m, f.alpha);
  return m;
}

/// Step 4: the layout's largest rank, every view node's level 0 copied in,
/// the mips.
void assemble(const std::vector<ViewFactors>& factors, ClothMaterial& material) {
  material.max_rank = 0;
  for (const ViewFactors& f : factors) material.max_rank = std::max(material.max_rank, f.rank);
  material.allocate();
  const size_t r = size_t(material.max_rank);
  const size_t texels = material.layout().level_texels(0);
  const int n_lights = material.light_count();
  const int ch = material.layout().channels;
  for (int v = 0; v < material.view_count(); ++v) {
    const ViewFactors& f = factors[size_t(v)];
    if (f.alpha.empty()) continue;  // another part's view node (material_shard.h)
    material.rank[v] = f.rank;
    material.error[v] = f.error;
    for (size_t t = 0; t < texels; ++t) {
      material.alpha[0][size_t(v) * texels + t] = f.alpha[t];
      for (int k = 0; k < f.rank; ++k) {
        const float* c = &f.coefficients[(t * f.rank + k) * size_t(ch)];
        material.coefficients[0][(size_t(v) * texels + t) * r + k] = V3f(c[0], c[1], c[2]);
        if (ch == 5)
          material.coefficients_next[0][(size_t(v) * texels + t) * r + k] = Imath::V2f(c[3], c[4]);
      }
    }
    for (int n = 0; n < n_lights; ++n)
      for (int k = 0; k < f.rank; ++k)
        material.light_factors[(size_t(v) * n_lights + n) * r + k] =
            f.light[size_t(n) * f.rank + k];
  }
  material.build_mips();
}

/// What the bake's steps share: the material being filled and what it is
/// baked from, the view nodes this part bakes, each view node's factors,
/// the threads' work space and the progress.
struct BakeRun {
  ClothMaterial& material;
  const VolumeTexture& volume;
  const FiberShader& shader;
  const std::function<void(double)>& progress;
  std::vector<int> views;
  LightNodeDirections light_nodes;
  std::vector<ViewFactors> factors;
  tbb::enumerable_thread_specific<ViewLocal> locals;
  std::mutex progress_mutex;
  uint64_t field_bytes_built = 0;
  double marches_per_block = 1.0;  // addressed per crossing: its members
  double fields_seconds = 0.0, marches_seconds = 0.0, factorise_seconds = 0.0;

  int view_count() const { return int(views.size()); }
  /// Serialised: `progress` is called from workers.
  void report(double fraction) {
    if (!progress) return;
    std::lock_guard lock(progress_mutex);
    progress(fraction);
  }
};

/// Steps 2 and 3 addressed per crossing: block by block, its light fields
/// over the window of `context` crossings around its representative, then
/// every view node's rows of that block (the view nodes' matrices and fibre
/// tables are held across the blocks; one window's fields at a time); then
/// each view node factorised.
void bake_crossings(BakeRun& run) {
  const ClothMaterial& material = run.material;
  const MaterialSettings& settings = material.settings;
  const int n_views = run.view_count(), n_lights = material.light_count();
  const int R = settings.texels, rows = material.layout().level_rows(0);
  const int ch = material.layout().channels;
  const bool tabulate = tabulates_fiber(settings, material.optics);
  std::vector<Eigen::MatrixXf> matrices(static_cast<size_t>(n_views));
  std::vector<FiberLightTable> tables(tabulate ? size_t(n_views) : 0);
  auto t0 = std::chrono::steady_clock::now();
  tbb::parallel_for(0, n_views, [&](int i) {
    matrices[size_t(i)].setZero(Eigen::Index(R) * rows * ch, n_lights);
    run.factors[size_t(run.views[size_t(i)])].alpha.assign(size_t(R) * rows, 0.0f);
    if (tabulate)
      build_fiber_table(material, run.shader, run.light_nodes.local, run.views[size_t(i)],
                        tables[size_t(i)], run.locals.local().counts);
  });
  std::vector<std::vector<CrossingClasses::Crossing>> members;
  size_t marches = 0;
  for (int b = 0; b < material.crossings.count(); ++b) {
    members.push_back(material.crossings.members(b, settings.members));
    marches += members.back().size();
  }
  run.marches_seconds += seconds_since(t0);
  run.marches_per_block = double(marches) / double(std::max<size_t>(members.size(), 1));
  const double steps = double(marches) * n_views + n_views;
  std::atomic<int> steps_done{0};
  for (size_t b = 0; b < members.size(); ++b)
    for (const CrossingClasses::Crossing& c : members[b]) {
      // The block is the mean of its members' marches (one member: the
      // representative's, assigned as a whole-repeat bake's texels are).
      const float weight = members[b].size() == 1 ? 1.0f : 1.0f / float(members[b].size());
      const BlockWindow w = crossing_window(material, run.volume, c);
      t0 = std::chrono::steady_clock::now();
      const LightFieldSet fields = LightFieldSet::build_window(
          run.volume, w.x0, w.y0, w.cells_x, w.cells_y, run.light_nodes.texture,
          material.optics.extinction_per_mm, settings.field_supersample, settings.light_fields);
      run.field_bytes_built = std::max<uint64_t>(run.field_bytes_built, fields.bytes());
      run.fields_seconds += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      tbb::parallel_for(0, n_views, [&](int i) {
        const int view = run.views[size_t(i)];
        march_view_rows(material, run.volume, run.shader, fields, run.light_nodes.local, view,
                        int(b) * R, int(b + 1) * R, tabulate ? &tables[size_t(i)] : nullptr,
                        run.locals.local(), matrices[size_t(i)], run.factors[size_t(view)].alpha,
                        &c, weight);
        run.report(double(++steps_done) / steps);
      });
      run.marches_seconds += seconds_since(t0);
    }
  tables.clear();
  t0 = std::chrono::steady_clock::now();
  tbb::parallel_for(0, n_views, [&](int i) {
    ViewFactors& f = run.factors[size_t(run.views[size_t(i)])];
    factorise(matrices[size_t(i)], settings.max_error, ch, f);
    matrices[size_t(i)] = Eigen::MatrixXf();
    run.report(double(++steps_done) / steps);
  });
  run.factorise_seconds = seconds_since(t0);
}

/// Steps 2 and 3 over the whole repeat, per view node: march every texel
/// for all light nodes, then factorise. Throws InputError on "memory" once
/// the fields (`fields_bytes`) and the factorised table pass `budget`.
void bake_repeat(BakeRun& run, uint64_t fields_bytes, uint64_t budget) {
  const ClothMaterial& material = run.material;
  const MaterialSettings& settings = material.settings;
  const auto t_fields = std::chrono::steady_clock::now();
  const LightFieldSet fields =
      LightFieldSet::build(run.volume, run.light_nodes.texture, material.optics.extinction_per_mm,
                           settings.field_supersample, settings.light_fields);
  run.field_bytes_built = fields.bytes();
  run.fields_seconds = seconds_since(t_fields);
  std::atomic<uint64_t> table_bytes{0};
  std::atomic<int> views_done{0};
  std::atomic<bool> over_budget{false};
  // CPU nanoseconds of the two parts of a view's task, to split their wall time.
  std::atomic<uint64_t> march_ns{0}, factorise_ns{0};
  const int n_views = run.view_count();
  const auto t_views = std::chrono::steady_clock::now();
  tbb::parallel_for(0, n_views, [&](int i) {
    if (over_budget) return;
    const int view = run.views[size_t(i)];
    ViewFactors& f = run.factors[size_t(view)];
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixXf m = march_view_node(material, run.volume, run.shader, fields,
                                              run.light_nodes.local, view, run.locals.local(), f);
    const auto t1 = std::chrono::steady_clock::now();
    factorise(m, settings.max_error, material.layout().channels, f);
    march_ns += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    factorise_ns += uint64_t(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t1)
            .count());
    const uint64_t bytes = table_bytes +=
        (f.coefficients.size() + f.light.size() + f.alpha.size()) * sizeof(float);
    if (fields_bytes + bytes > budget) over_budget = true;
    run.report(double(++views_done) / double(n_views));
  });
  const double wall = seconds_since(t_views);
  const double busy = double(march_ns + factorise_ns);
  run.marches_seconds = busy > 0.0 ? wall * double(march_ns) / busy : 0.0;
  run.factorise_seconds = wall - run.marches_seconds;
  if (over_budget)
    throw InputError("memory", "the factorised table grew past the budget of " +
                                   std::to_string(budget >> 20) +
                                   " MiB; raise max_error, lower texels or directions, or raise "
                                   "the memory budget");
}

/// What the bake did, counted over the threads.
MaterialBakeStats bake_stats(const BakeRun& run) {
  MaterialBakeStats stats;
  for (const ViewLocal& l : run.locals) {
    stats.march_samples += l.counts.samples;
    stats.fiber_evaluations += l.counts.fiber_evaluations;
  }
  const ClothMaterial& material = run.material;
  const size_t texels = material.layout().level_texels(0);
  const double n_views = double(run.view_count());
  stats.rays = uint64_t(n_views * double(texels) * material.settings.spp * run.marches_per_block);
  stats.field_bytes = run.field_bytes_built;
  stats.fields_seconds = run.fields_seconds;
  stats.marches_seconds = run.marches_seconds;
  stats.factorise_seconds = run.factorise_seconds;
  stats.uncompressed_values =
      n_views * double(texels) * material.light_count() * material.layout().channels;
  return stats;
}
}  // namespace

// The bake's four steps in order (material_bake.h).
ClothMaterial bake_material(const MaterialSource& source, const MaterialSettings& settings,
                            uint64_t memory_budget, const std::function<void(double)>& progress,
                            MaterialBakeStats* stats, const MaterialShard& shard) {
  check_material_bake(source, settings, shard);
  ClothMaterial material = unbaked_material(source, settings);
  material.shard = shard;
  BakeRun run{material, *source.volume, *source.shader, progress};
  run.views = material_shard_views(material.view_grid, shard);
  // Step 1: the light fields, one per light node, over the whole repeat (or
  // a block's window).
  run.light_nodes = light_node_directions(material);
  const uint64_t fields_bytes = material_field_bytes(material, *source.volume);
  if (fields_bytes > memory_budget)
    throw InputError("memory", "the light fields need " + std::to_string(fields_bytes >> 20) +
                                   " MiB, over the budget of " +
                                   std::to_string(memory_budget >> 20) +
                                   " MiB; lower light_directions or raise the memory budget");
  run.factors.resize(size_t(material.view_count()));
  if (material.addressed())
    bake_crossings(run);
  else
    bake_repeat(run, fields_bytes, memory_budget);
  const auto t_assemble = std::chrono::steady_clock::now();
  assemble(run.factors, material);
  const double assemble_seconds = seconds_since(t_assemble);
  // A part holds a share of the view nodes: the merge fits the whole.
  if (material.settings.view_parallax && shard.whole())
    material.parallax_depth_mm = fit_view_parallax(material).depth_mm;
  if (stats) {
    *stats = bake_stats(run);
    stats->assemble_seconds = assemble_seconds;
  }
  return material;
}

std::vector<int> probe_view_ranks(const MaterialSource& source, const ClothMaterial& material,
                                  std::span<const int> views) {
  const LightNodeDirections nodes = light_node_directions(material);
  const MaterialSettings& s = material.settings;
  // One field point per cell edge: the fields' build is most of the probe's
  // time, and the ranks the coarser fields give are the bake's to within
  // the probe's own spread (lab/real_drafts).
  const LightFieldSet fields =
      LightFieldSet::build(*source.volume, nodes.texture, material.optics.extinction_per_mm,
                           std::min(s.field_supersample, k_rank_probe_field_supersample),
                           s.light_fields);
  std::vector<int> ranks(views.size(), 0);
  tbb::enumerable_thread_specific<ViewLocal> locals;
  tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
    ViewFactors f;
    const Eigen::MatrixXf m = march_view_node(material, *source.volume, *source.shader, fields,
                                              nodes.local, views[i], locals.local(), f);
    factorise(m, s.max_error, material.layout().channels, f);
    ranks[i] = f.rank;
  });
  return ranks;
}

void check_material_memory(const ClothMaterial& material, const VolumeTexture& volume, int threads,
                           uint64_t memory_budget) {
  const uint64_t fixed = material_bake_fixed_bytes(material, volume, threads);
  if (fixed > memory_budget)
    throw InputError("memory", "the bake needs at least " + std::to_string(fixed >> 20) +
                                   " MiB (light fields and one view's table per thread), over "
                                   "the budget of " +
                                   std::to_string(memory_budget >> 20) + " MiB");
}

}  // namespace clothbake
