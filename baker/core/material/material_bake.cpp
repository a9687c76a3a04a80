#include "core/material/material_bake.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <string>

#include <Eigen/Dense>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/march/sample_march.h"
#include "core/material/material_shard.h"
#include "core/material/view_parallax.h"
#include "core/util/error.h"
#include "core/util/random.h"

namespace clothbake {

namespace {
using Imath::V3f;

bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

/// One view node's factorised table at level 0, before the layout's
/// largest rank is known.
struct ViewFactors {
  int rank = 0;
  float error = 0.0f;
  std::vector<float> coefficients;  // [texel * rank + k] * channels + c
  std::vector<float> light;         // [node * rank + k]
  std::vector<float> alpha;         // [texel]
};

/// The truncated SVD of m (rows: texels x RGB, columns: light nodes) through
/// its Gram matrix m^T m, whose eigenvectors are the right singular vectors:
/// cheaper than an SVD of the tall matrix (one product of rows x nodes^2,
/// then an eigensolve of nodes x nodes) and exact to double precision in
/// the solve. Keeps the smallest rank whose relative Frobenius error is at
/// most `max_error`. Scaled so that the light factor's entries are of order
/// 1 and the coefficients of order of a radiance.
void factorise(const Eigen::MatrixXf& m, float max_error, int channels, ViewFactors& out) {
  const Eigen::Index nodes = m.cols(), rows = m.rows();
  const Eigen::MatrixXd gram = (m.transpose() * m).cast<double>();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  const Eigen::VectorXd lambda = eig.eigenvalues().reverse().cwiseMax(0.0);  // descending
  const double total = lambda.sum();
  int rank = 0;
  double kept = 0.0;
  if (total > 0.0) {
    const double allowed = double(max_error) * double(max_error) * total;
    while (rank < nodes && total - kept > allowed) kept += lambda[rank++];
  }
  out.rank = rank;
  out.error = total > 0.0 ? float(std::sqrt(std::max(0.0, total - kept) / total)) : 0.0f;
  if (rank == 0) return;
  Eigen::MatrixXf v = eig.eigenvectors().rightCols(rank).rowwise().reverse().cast<float>();
  // One sign per component: the light factor sums to >= 0 (eigenvectors'
  // signs are arbitrary; this keeps them reproducible and readable).
  for (int k = 0; k < rank; ++k)
    if (v.col(k).sum() < 0.0f) v.col(k) = -v.col(k);
  const float scale = std::sqrt(float(nodes));
  const Eigen::MatrixXf u = (m * v) / scale;  // rows x rank
  v *= scale;
  const Eigen::Index texels = rows / channels;
  out.coefficients.resize(size_t(rows) * rank);
  for (Eigen::Index t = 0; t < texels; ++t)
    for (int k = 0; k < rank; ++k)
      for (int c = 0; c < channels; ++c)
        out.coefficients[(size_t(t) * rank + k) * channels + c] = u(t * channels + c, k);
  out.light.resize(size_t(nodes) * rank);
  for (Eigen::Index n = 0; n < nodes; ++n)
    for (int k = 0; k < rank; ++k) out.light[size_t(n) * rank + k] = v(n, k);
}
}  // namespace

void check_material_settings(const MaterialSettings& s) {
  auto range = [](const std::string& field, int value, int lo, int hi) {
    if (value < lo || value > hi)
      throw InputError(field, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                  "], got " + std::to_string(value));
  };
  range("texels", s.texels, k_min_material_texels, k_max_material_texels);
  if (!power_of_two(s.texels))
    throw InputError("texels", "must be a power of 2 (the mip levels halve it down to 1), got " +
                                   std::to_string(s.texels));
  range("directions", s.directions, k_min_material_directions, k_max_material_directions);
  range("light_directions", s.light_directions, k_min_material_directions,
        k_max_material_directions);
  range("spp", s.spp, k_min_material_spp, k_max_material_spp);
  range("context", s.context, k_min_material_context, k_max_material_context);
  range("members", s.members, k_min_material_members, k_max_material_members);
  range("phase_bins", s.phase_bins, k_min_phase_bins, k_max_phase_bins);
  range("field_supersample", s.field_supersample, k_min_field_supersample,
        k_max_field_supersample);
  if (s.fiber_tangent_nodes != 0)
    range("fiber_tangent_nodes", s.fiber_tangent_nodes, k_min_fiber_tangent_nodes,
          k_max_fiber_tangent_nodes);
  if (!(s.max_error >= k_min_material_error && s.max_error <= k_max_material_error))
    throw InputError("max_error", "must be in [0, 1], got " + std::to_string(s.max_error));
}

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
  m.settings.light_fields = LightFieldSet::resolve(settings.light_fields, volume,
                                                   optics.extinction_per_mm,
                                                   settings.field_supersample);
  return m;
}

std::vector<V3f> material_light_directions(const ClothMaterial& material) {
  std::vector<V3f> out(size_t(material.light_count()));
  for (int n = 0; n < material.light_count(); ++n) out[n] = material.light_grid.bake_direction(n);
  return out;
}

LightNodeDirections light_node_directions(const ClothMaterial& material,
                                          std::span<const int> nodes) {
  LightNodeDirections out;
  auto add = [&](int n) {
    const V3f d_material = material.light_grid.bake_direction(n);
    out.local.push_back(material.local_from_material(d_material));
    out.texture.push_back(material.texture_from_material(d_material));
  };
  if (nodes.empty())
    for (int n = 0; n < material.light_count(); ++n) add(n);
  else
    for (int n : nodes) add(n);
  return out;
}

NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const V3f> light_local, int view, int x, int y, int k) {
  return material_sample(material, volume, shader, fields, light_local, view, x, y, k,
                         material.addressed()
                             ? material.crossings.representative[size_t(y / material.texels())]
                             : CrossingClasses::Crossing{});
}

NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const V3f> light_local, int view, int x, int y, int k,
                               const CrossingClasses::Crossing& c) {
  const MaterialSettings& s = material.settings;
  const MaterialOptics& o = material.optics;
  // Addressed per crossing, row y of level 0 lies in block y / R, at a
  // crossing of its class (`c`); its samples are seeded as the texel a
  // whole repeat of R texels per thread would hold there, so that where
  // every crossing is its own class the two bakes march the same samples.
  const uint64_t seed_x = material.addressed() ? uint64_t(c.end) * s.texels + x : uint64_t(x);
  const uint64_t seed_y =
      material.addressed() ? uint64_t(c.pick) * s.texels + uint64_t(y % s.texels) : uint64_t(y);
  Rng rng(hash_key(s.seed, rng_stream::material, uint64_t(view), seed_x, seed_y, uint64_t(k)));
  const V3f size = volume.size_mm();
  float px, py;
  if (material.addressed()) {
    const ThreadSpan sx = thread_span(*material.warp_threads, c.end);
    const ThreadSpan sy = thread_span(*material.weft_threads, c.pick);
    px = sx.left_mm + (float(x) + rng.next_float()) / float(s.texels) * sx.width_mm();
    py = sy.left_mm + (float(y % s.texels) + rng.next_float()) / float(s.texels) * sy.width_mm();
  } else {
    px = (float(x) + rng.next_float()) / float(s.texels) * size.x;
    py = (float(y) + rng.next_float()) / float(s.texels) * size.y;
  }
  const V3f to_eye = material.view_grid.bake_direction(view);
  NodeMarchInput in;
  in.volume = &volume;
  in.shader = &shader;
  in.fields = &fields;
  in.to_light_local = light_local;
  in.to_eye_local = material.local_from_material(to_eye);
  in.depth_scale = o.depth_scale;
  in.sqrt_aspect = std::sqrt(o.aspect);
  in.dir_texture = -material.texture_from_material(to_eye);
  // The entry as ClothScene::shade_surface places it: the top-face point
  // from the front; from behind, the bottom face below it along the ray.
  const SlabEntry slab = slab_entry(volume, V3f(px, py, size.z), in.dir_texture);
  in.entry_texture = slab.entry_texture;
  in.length_mm = slab.length_mm;
  in.extinction_per_mm = o.extinction_per_mm;
  const V3f cell = volume.cell_size_mm();
  in.step_mm = o.step_cells * std::min({cell.x, cell.y, cell.z});
  in.cutoff = o.cutoff;
  in.jitter = rng.next_float();
  in.seed = rng.next_u64();
  in.shading = o.shading;
  in.isotropic_albedo = o.isotropic_albedo;
  in.roulette = o.light_roulette;
  in.colour_parts = material.colour_parts();
  if (in.colour_parts) {
    in.warp_threads = material.warp_threads.get();
    in.weft_threads = material.weft_threads.get();
    in.own_end = in.warp_threads->owner(px);
    in.own_pick = in.weft_threads->owner(py);
  }
  return in;
}

ThreadSpan thread_span(const ThreadLayout& threads, int i) {
  return ThreadSpan{0.5f * (threads.centre_mm(i - 1) + threads.centre_mm(i)),
                    0.5f * (threads.centre_mm(i) + threads.centre_mm(i + 1))};
}

BlockWindow crossing_window(const ClothMaterial& material, const VolumeTexture& volume,
                            const CrossingClasses::Crossing& c) {
  const V3f cell = volume.cell_size_mm();
  const int w = material.settings.context;
  const float x0 = thread_span(*material.warp_threads, c.end - w).left_mm;
  const float x1 = thread_span(*material.warp_threads, c.end + w).right_mm;
  const float y0 = thread_span(*material.weft_threads, c.pick - w).left_mm;
  const float y1 = thread_span(*material.weft_threads, c.pick + w).right_mm;
  BlockWindow b;
  b.x0 = int(std::floor(x0 / cell.x));
  b.y0 = int(std::floor(y0 / cell.y));
  b.cells_x = std::min(volume.nx(), int(std::ceil(x1 / cell.x)) - b.x0);
  b.cells_y = std::min(volume.ny(), int(std::ceil(y1 / cell.y)) - b.y0);
  return b;
}

std::vector<BlockWindow> block_windows(const ClothMaterial& material, const VolumeTexture& volume) {
  std::vector<BlockWindow> out;
  if (!material.addressed()) return out;
  for (const CrossingClasses::Crossing& c : material.crossings.representative)
    out.push_back(crossing_window(material, volume, c));
  return out;
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
        fields, LightFieldSet::bytes_for_window(volume, b.cells_x, b.cells_y, layout.light_count(), s,
                                                method));
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
  return fields + uint64_t(layout.view_count()) *
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
  table.build(shader, light_local, material.local_from_material(material.view_grid.bake_direction(view)), k);
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
  if (tabulate) build_fiber_table(material, shader, light_local, view, local.fiber_table, local.counts);
  Eigen::MatrixXf m(Eigen::Index(R) * R * material.layout().channels, Eigen::Index(light_local.size()));
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
        material.light_factors[(size_t(v) * n_lights + n) * r + k] = f.light[size_t(n) * f.rank + k];
  }
  material.build_mips();
}
}  // namespace

// The bake's four steps in order (material_bake.h).
ClothMaterial bake_material(const VolumeTexture& volume, const FiberShader& shader,
                            const MaterialOptics& optics, const MaterialSettings& settings,
                            uint64_t memory_budget, const std::function<void(double)>& progress,
                            MaterialBakeStats* stats, const ClothSpec* colour_free_cloth,
                            const MaterialShard& shard) {
  check_material_settings(settings);
  if (settings.parts == MaterialParts::SpecularWarpWeft && !colour_free_cloth)
    throw InputError("parts", "colour-free parts need the colour-free cloth the volume is of");
  if (!(optics.depth_scale > 0.0f) || !std::isfinite(optics.depth_scale))
    throw InputError("depth_scale", "must be positive and finite");
  if (settings.parts == MaterialParts::SpecularWarpWeft && optics.shading != ShadingMode::Fiber)
    throw InputError("parts", "colour-free parts need fibre shading (isotropic shading has one "
                              "albedo and no yarn colours)");
  if (settings.address == MaterialAddress::Crossings) {
    if (settings.parts != MaterialParts::SpecularWarpWeft)
      throw InputError("address", "a material addressed per crossing needs colour-free parts (its "
                                  "blocks are found from the cloth's threads)");
    if (!shard.whole())
      throw InputError("shard", "a material addressed per crossing is baked whole");
  }
  ClothMaterial material = unbaked_material(volume, optics, settings);
  if (material.colour_parts()) material.set_cloth(*colour_free_cloth, palette_of(*colour_free_cloth));
  const int n_lights = material.light_count();
  material.shard = shard;
  const std::vector<int> views = material_shard_views(material.view_grid, shard);
  const int n_views = int(views.size());

  // Step 1: the light fields, one per light node, over the whole repeat.
  const LightNodeDirections light_nodes = light_node_directions(material);
  const std::vector<V3f>& light_local = light_nodes.local;
  const std::vector<V3f>& light_texture = light_nodes.texture;
  const uint64_t fields_bytes = material_field_bytes(material, volume);
  if (fields_bytes > memory_budget)
    throw InputError("memory", "the light fields need " + std::to_string(fields_bytes >> 20) +
                                   " MiB, over the budget of " +
                                   std::to_string(memory_budget >> 20) +
                                   " MiB; lower --light-directions or raise --memory");
  std::vector<ViewFactors> factors(size_t(material.view_count()));
  tbb::enumerable_thread_specific<ViewLocal> locals;
  std::atomic<uint64_t> table_bytes{0};
  std::atomic<int> views_done{0};
  std::mutex progress_mutex;
  std::atomic<bool> over_budget{false};
  uint64_t field_bytes_built = 0;
  double marches_per_block = 1.0;  // addressed per crossing: its members
  if (material.addressed()) {
    // Per crossing: block by block, its light fields over the window of
    // `context` crossings around its representative, then every view
    // node's rows of that block (the view nodes' matrices and fibre tables
    // are held across the blocks; one window's fields at a time).
    const int R = settings.texels, rows = material.layout().level_rows(0);
    const int ch = material.layout().channels;
    const bool tabulate = tabulates_fiber(settings, optics);
    std::vector<Eigen::MatrixXf> matrices(static_cast<size_t>(n_views));
    std::vector<FiberLightTable> tables(tabulate ? size_t(n_views) : 0);
    tbb::parallel_for(0, n_views, [&](int i) {
      matrices[size_t(i)].setZero(Eigen::Index(R) * rows * ch, n_lights);
      factors[size_t(views[size_t(i)])].alpha.assign(size_t(R) * rows, 0.0f);
      if (tabulate)
        build_fiber_table(material, shader, light_local, views[size_t(i)], tables[size_t(i)],
                          locals.local().counts);
    });
    std::vector<std::vector<CrossingClasses::Crossing>> members;
    size_t marches = 0;
    for (int b = 0; b < material.crossings.count(); ++b) {
      members.push_back(material.crossings.members(b, settings.members));
      marches += members.back().size();
    }
    marches_per_block = double(marches) / double(std::max<size_t>(members.size(), 1));
    const double steps = double(marches) * n_views + n_views;
    std::atomic<int> steps_done{0};
    for (size_t b = 0; b < members.size(); ++b)
      for (const CrossingClasses::Crossing& c : members[b]) {
        // The block is the mean of its members' marches (one member: the
        // representative's, assigned as a whole-repeat bake's texels are).
        const float weight = members[b].size() == 1 ? 1.0f : 1.0f / float(members[b].size());
        const BlockWindow w = crossing_window(material, volume, c);
        const LightFieldSet fields =
            LightFieldSet::build_window(volume, w.x0, w.y0, w.cells_x, w.cells_y, light_texture,
                                        optics.extinction_per_mm, settings.field_supersample,
                                        material.settings.light_fields);
        field_bytes_built = std::max<uint64_t>(field_bytes_built, fields.bytes());
        tbb::parallel_for(0, n_views, [&](int i) {
          const int view = views[size_t(i)];
          march_view_rows(material, volume, shader, fields, light_local, view, int(b) * R,
                          int(b + 1) * R, tabulate ? &tables[size_t(i)] : nullptr,
                          locals.local(), matrices[size_t(i)], factors[size_t(view)].alpha, &c,
                          weight);
          const int done = ++steps_done;
          if (progress) {
            std::lock_guard lock(progress_mutex);
            progress(double(done) / steps);
          }
        });
      }
    tables.clear();
    tbb::parallel_for(0, n_views, [&](int i) {
      ViewFactors& f = factors[size_t(views[size_t(i)])];
      factorise(matrices[size_t(i)], settings.max_error, ch, f);
      matrices[size_t(i)] = Eigen::MatrixXf();
      const int done = ++steps_done;
      if (progress) {
        std::lock_guard lock(progress_mutex);
        progress(double(done) / steps);
      }
    });
  } else {
    // Steps 2 and 3, per view node: march every texel for all light nodes,
    // then factorise.
    const LightFieldSet fields =
        LightFieldSet::build(volume, light_texture, optics.extinction_per_mm,
                             settings.field_supersample, material.settings.light_fields);
    field_bytes_built = fields.bytes();
    tbb::parallel_for(0, n_views, [&](int i) {
      if (over_budget) return;
      const int view = views[size_t(i)];
      ViewFactors& f = factors[size_t(view)];
      const Eigen::MatrixXf m = march_view_node(material, volume, shader, fields, light_local,
                                                view, locals.local(), f);
      factorise(m, settings.max_error, material.layout().channels, f);
      const uint64_t bytes =
          table_bytes += (f.coefficients.size() + f.light.size() + f.alpha.size()) * sizeof(float);
      if (fields_bytes + bytes > memory_budget) over_budget = true;
      const int done = ++views_done;
      if (progress) {
        std::lock_guard lock(progress_mutex);
        progress(double(done) / double(n_views));
      }
    });
  }
  if (over_budget)
    throw InputError("memory", "the factorised table grew past the budget of " +
                                   std::to_string(memory_budget >> 20) +
                                   " MiB; raise --max-error, lower --texels or --directions, or "
                                   "raise --memory");
  assemble(factors, material);
  // A part holds a share of the view nodes: the merge fits the whole.
  if (material.settings.view_parallax && shard.whole())
    material.parallax_depth_mm = fit_view_parallax(material).depth_mm;
  if (stats) {
    *stats = MaterialBakeStats{};
    for (const ViewLocal& l : locals) {
      stats->march_samples += l.counts.samples;
      stats->fiber_evaluations += l.counts.fiber_evaluations;
    }
    const size_t texels = material.layout().level_texels(0);
    stats->rays = uint64_t(double(n_views) * double(texels) * settings.spp * marches_per_block);
    stats->field_bytes = field_bytes_built;
    stats->uncompressed_values = double(n_views) * double(texels) * n_lights * material.layout().channels;
  }
  return material;
}

}  // namespace clothbake
