#include "core/material_bake/material_probe.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include "core/material_bake/bake_memory.h"
#include "core/material_bake/material_bake.h"
#include "core/material_bake/material_sample.h"
#include "core/material_bake/material_shard.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"

namespace clothbake {

namespace {
using Clock = std::chrono::steady_clock;
using Imath::V3f;

/// `count` distinct node indices of [0, n) picked by the golden-ratio
/// sequence. Nodes cost differently by direction (horizon nodes march or
/// build longest), and node indices run row by row over a K x K grid: even
/// strides keep hitting the same column (with K = 16 and 8 picks of 512,
/// all on the horizon), the golden ratio mixes rows and columns.
std::vector<int> pick_nodes(int n, int count) {
  std::vector<int> out;
  std::vector<bool> taken(size_t(n), false);
  double x = 0.5;
  while (int(out.size()) < std::min(n, count)) {
    int i = std::min(n - 1, int(x * double(n)));
    while (taken[size_t(i)]) i = (i + 1) % n;
    taken[size_t(i)] = true;
    out.push_back(i);
    x += 0.6180339887498949;
    x -= std::floor(x);
  }
  return out;
}

/// The probe's light nodes: their directions in both frames, and the
/// fields of all P of them and of the first alone.
struct ProbeLights {
  std::vector<V3f> local, texture;
  LightFieldSet fields_p, fields_1;
};

/// Step 1: P light nodes' fields, spread over the grid; and the first of
/// them alone, for the marches' cost per light node.
ProbeLights probe_fields(const ClothMaterial& material, const VolumeTexture& volume,
                         MaterialEstimate& e) {
  const int L = material.light_count(), P = std::min(L, k_probe_light_nodes);
  const MaterialSettings& s = material.settings;
  const float sigma = material.optics.extinction_per_mm;
  e.probe_light_nodes = P;
  ProbeLights p;
  LightNodeDirections picked = light_node_directions(material, pick_nodes(L, P));
  p.local = std::move(picked.local);
  p.texture = std::move(picked.texture);
  // Per crossing: the first block's window, times the blocks (their windows
  // are alike in size).
  const std::vector<BlockWindow> windows = block_windows(material, volume);
  const BlockWindow whole{0, 0, volume.nx(), volume.ny()};
  const BlockWindow& w = windows.empty() ? whole : windows.front();
  // Each block marches its members (settings.members, fewer where a class
  // has fewer crossings), each under its own window's fields.
  double blocks = 1.0;
  if (!windows.empty()) {
    blocks = 0.0;
    for (int b = 0; b < material.crossings.count(); ++b)
      blocks += double(material.crossings.members(b, s.members).size());
  }
  e.marches_per_block = windows.empty() ? 1.0 : blocks / double(windows.size());
  const auto t0 = Clock::now();
  p.fields_p = LightFieldSet::build_window(volume, w.x0, w.y0, w.cells_x, w.cells_y, p.texture,
                                           sigma, s.field_supersample, s.light_fields);
  e.fields_seconds = seconds_since(t0) * double(L) / double(P) * blocks;
  p.fields_1 = LightFieldSet::build_window(volume, w.x0, w.y0, w.cells_x, w.cells_y,
                                           std::span(p.texture).first(1), sigma,
                                           s.field_supersample, s.light_fields);
  return p;
}

/// Per thread: the probe's fibre tables, march scratch and core-seconds.
struct ProbeLocal {
  FiberLightTable table_1, table_p;
  NodeMarchScratch scratch_1, scratch_p;
  NodeMarchCounts counts;
  std::vector<V3f> radiance, radiance_next;
  double table_core = 0.0, march_1_core = 0.0, march_p_core = 0.0;
};

/// Step 2: probe views spread over both hemispheres, on the bake's threads.
/// Probe view i marches a run of consecutive rays (texels in the bake's
/// order, row by row, spp each) starting at a point of the repeat picked per
/// view: consecutive texels read neighbouring light-field points, and the
/// bake's speed depends on that (rays scattered over the repeat ran 10 times
/// slower per ray with the 200 nodes' fields). Each ray is marched for 1 and
/// for P light nodes in turn, so that a burst of other work on the machine
/// slows both alike: their difference is what is extrapolated.
void probe_marches(const ClothMaterial& material, const VolumeTexture& volume,
                   const FiberShader& shader, const ProbeLights& lights, int threads,
                   MaterialEstimate& e) {
  const MaterialSettings& s = material.settings;
  const int V = material.view_count(), L = material.light_count(), R = s.texels;
  const int P = int(lights.local.size());
  const int VP = std::min(V, k_probe_view_nodes);
  e.probe_view_nodes = VP;
  const std::vector<int> views = pick_nodes(V, VP);
  const uint64_t rays_per_view = material.layout().level_texels(0) * uint64_t(s.spp);
  const uint64_t probe_rays = std::min<uint64_t>(rays_per_view, k_probe_rays_per_view);
  e.probe_rays = probe_rays * uint64_t(VP);
  const auto first_ray = [&](int i) {
    const double x = double(i) * 0.6180339887498949 + 0.25;
    return uint64_t((x - std::floor(x)) * double(rays_per_view - probe_rays));
  };
  const bool tabulate = tabulates_fiber(s, material.optics);
  const std::span<const V3f> lights_p(lights.local), lights_1 = lights_p.first(1);
  tbb::enumerable_thread_specific<ProbeLocal> locals;
  tbb::parallel_for(0, VP, [&](int i) {
    ProbeLocal& local = locals.local();
    const int view = views[size_t(i)];
    if (tabulate) {
      const V3f to_eye = material.view_grid.bake_direction(view);
      local.table_1.build(shader, lights_1, to_eye, s.fiber_tangent_nodes);
      const auto tt = Clock::now();
      local.table_p.build(shader, lights_p, to_eye, s.fiber_tangent_nodes);
      local.table_core += seconds_since(tt);
    }
    local.scratch_1.view_tag = local.scratch_p.view_tag = uint32_t(view) + 1;
    local.radiance.resize(size_t(P));
    local.radiance_next.resize(size_t(P));
    for (uint64_t r = first_ray(i); r < first_ray(i) + probe_rays; ++r) {
      const int k = int(r % uint64_t(s.spp)), t = int(r / uint64_t(s.spp));
      for (int pass = 0; pass < 2; ++pass) {
        const auto tm = Clock::now();
        NodeMarchInput in =
            material_sample(material, volume, shader, pass == 0 ? lights.fields_1 : lights.fields_p,
                            pass == 0 ? lights_1 : lights_p, view, t % R, t / R, k);
        if (tabulate) in.fiber_table = pass == 0 ? &local.table_1 : &local.table_p;
        std::fill(local.radiance.begin(), local.radiance.end(), V3f(0.0f));
        if (in.length_mm > 0.0f)
          march_view_ray_all_lights(in, local.radiance.data(),
                                    pass == 0 ? local.scratch_1 : local.scratch_p, local.counts,
                                    local.radiance_next.data());
        (pass == 0 ? local.march_1_core : local.march_p_core) += seconds_since(tm);
      }
    }
  });
  double table_core = 0.0, march_1_core = 0.0, march_p_core = 0.0;
  for (const ProbeLocal& l : locals) {
    table_core += l.table_core;
    march_1_core += l.march_1_core;
    march_p_core += l.march_p_core;
  }
  // Per ray at L nodes: linear through the 1-node and P-node costs.
  const double per_ray_1 = march_1_core / double(e.probe_rays);
  const double per_ray_p = march_p_core / double(e.probe_rays);
  const double per_ray =
      P > 1 ? per_ray_1 + std::max(0.0, per_ray_p - per_ray_1) * double(L - 1) / double(P - 1)
            : per_ray_p;
  const double per_view_table = table_core / double(VP) * double(L) / double(P);
  e.marches_seconds =
      (per_view_table * double(V) + per_ray * double(e.rays)) / double(std::max(threads, 1));
}

/// Step 3: one view's factorisation, at the real size (channels x R^2 rows by L light
/// nodes) up to 64 x 64 texels, on a matrix of the same shape; the products
/// scale with the rows, the eigensolve does not. Every view's is the same work.
double probe_factorise(const MaterialLayout& layout, int threads) {
  const uint64_t texels = layout.level_texels(0);
  const Eigen::Index rows = Eigen::Index(std::min<uint64_t>(texels, 64 * 64)) * layout.channels;
  const double row_scale = double(texels) * double(layout.channels) / double(rows);
  const Eigen::MatrixXf m = Eigen::MatrixXf::Random(rows, layout.light_count()).cwiseAbs();
  const auto tg = Clock::now();
  const Eigen::MatrixXd gram = (m.transpose() * m).cast<double>();
  const double gram_seconds = seconds_since(tg);
  const auto te = Clock::now();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  const double eigen_seconds = seconds_since(te);
  const auto tu = Clock::now();
  const Eigen::MatrixXf u = m * eig.eigenvectors().cast<float>();
  const double product_seconds = seconds_since(tu);
  return ((gram_seconds + product_seconds) * row_scale + eigen_seconds +
          (u.size() > 0 ? 0.0 : 1.0)) *  // keeps u from being optimised away
         double(layout.view_count()) /
         double(std::max(threads, 1));
}

/// Step 4: the mips (one thread in the bake): timed on 8 views of up to
/// 256 x 256 texels at rank min(L, 8), scaled by views, texels and rank to
/// the full-rank table (an upper bound).
double probe_mips(const VolumeTexture& volume, const MaterialOptics& optics,
                  const MaterialSettings& settings, int blocks) {
  MaterialSettings small = settings;
  small.texels = std::min(settings.texels, 256);
  small.directions = 2;
  small.address = MaterialAddress::Repeat;
  ClothMaterial mips = unbaked_material(volume, optics, small);
  const MaterialLayout full = MaterialLayout::of(settings, blocks);
  mips.max_rank = std::min(full.light_count(), 8);
  mips.allocate();
  const auto tm = Clock::now();
  mips.build_mips();
  return seconds_since(tm) * double(full.view_count()) / double(mips.view_count()) *
         double(full.level_texels(0)) / double(mips.layout().level_texels(0)) *
         double(full.light_count()) / double(mips.max_rank);
}
}  // namespace

/// The whole repeat's ranks, probed: the views of a lattice inside each
/// hemisphere's grid (3 x 4 a hemisphere, away from the horizon's rim,
/// where the ranks are lowest) marched and factorised as the bake does.
/// Their mean stands for the mean; the largest rank among 512 view nodes
/// sits about k_rank_probe_max_margin over the lattice's largest (measured:
/// lab/real_drafts).
BakeRanks probe_ranks(const MaterialSource& source, const ClothMaterial& material) {
  const int K = material.settings.directions;
  std::vector<int> views;
  for (int h = 0; h < 2; ++h)
    for (const double fy : {0.15, 0.4, 0.65, 0.85})
      for (const double fx : {0.2, 0.5, 0.8}) {
        const int v = h * K * K + std::min(K - 1, int(fy * K)) * K + std::min(K - 1, int(fx * K));
        if (std::find(views.begin(), views.end(), v) == views.end()) views.push_back(v);
      }
  const std::vector<int> ranks = probe_view_ranks(source, material, views);
  BakeRanks r;
  for (const int k : ranks) {
    r.mean += double(k) / double(ranks.size());
    r.max = std::max(r.max, k);
  }
  r.max = std::min(material.light_count(), int(std::ceil(r.max * k_rank_probe_max_margin)));
  return r;
}

MaterialEstimate probe_material(const MaterialSource& source, const MaterialSettings& settings,
                                int threads, const MaterialShard& shard) {
  MaterialEstimate e;
  const auto probe_start = Clock::now();
  const VolumeTexture& volume = *source.volume;
  const FiberShader& shader = *source.shader;
  const MaterialOptics& optics = source.optics;
  if (settings.parts == MaterialParts::SpecularWarpWeft &&
      source.parts != MaterialParts::SpecularWarpWeft)
    throw InputError("parts", "colour-free parts need the colour-free cloth the volume is of");
  ClothMaterial material = unbaked_material(source, settings);
  const MaterialLayout layout = material.layout();
  e.view_nodes = layout.view_count();
  e.light_nodes = layout.light_count();
  e.light_field_bytes = material_field_bytes(material, volume);
  e.fixed_bytes = material_bake_fixed_bytes(material, volume, threads);
  e.max_bytes = layout.table_bytes(e.light_nodes);
  const BakeRanks ranks =
      material.addressed() ? expected_bake_ranks(material) : probe_ranks(source, material);
  e.expected_mean_rank = ranks.mean;
  e.expected_max_rank = ranks.max;
  e.bake_peak_bytes = bake_memory(material, volume, threads, ranks).peak();
  e.disk_bytes = uint64_t(k_disk_per_uncompressed * double(layout.file_bytes(ranks.mean)));

  const ProbeLights lights = probe_fields(material, volume, e);
  e.rays = uint64_t(double(e.view_nodes) * double(layout.level_texels(0)) * settings.spp *
                    e.marches_per_block);
  probe_marches(material, volume, shader, lights, threads, e);
  e.factorise_seconds = probe_factorise(layout, threads);
  e.mips_seconds = probe_mips(volume, optics, settings, material.crossings.count());
  e.whole_view_nodes = e.view_nodes;
  if (!shard.whole()) {
    const std::vector<int> views = material_shard_views(material.view_grid, shard);
    double mine = 0.0, all = 0.0;
    for (int v = 0; v < e.view_nodes; ++v) all += material_view_cost(material.view_grid, v);
    for (const int v : views) mine += material_view_cost(material.view_grid, v);
    const double view_share = double(views.size()) / double(e.view_nodes);
    e.shard = shard;
    e.shard_cost_share = mine / all;
    e.marches_seconds *= e.shard_cost_share;
    e.factorise_seconds *= e.shard_cost_share;
    e.mips_seconds *= view_share;
    e.rays = uint64_t(views.size()) * layout.level_texels(0) * uint64_t(settings.spp);
    e.max_bytes = uint64_t(double(e.max_bytes) * view_share);
    e.disk_bytes = uint64_t(double(e.disk_bytes) * view_share);
    e.view_nodes = int(views.size());
  }
  e.seconds = e.fields_seconds + e.marches_seconds + e.factorise_seconds + e.mips_seconds;
  e.probe_seconds = seconds_since(probe_start);
  return e;
}

}  // namespace clothbake
