#include "core/bake/baker.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include <tbb/parallel_for.h>

#include "core/util/error.h"
#include "core/util/random.h"

namespace clothbake {

namespace {
using Imath::V3f;

void check_settings(const BakeSettings& s) {
  // Errors name the setting; the command line maps it to its flag.
  if (s.directions < k_min_directions || s.directions > k_max_directions)
    throw InputError("directions", "K must be in [" + std::to_string(k_min_directions) + ", " +
                                       std::to_string(k_max_directions) + "], got " +
                                       std::to_string(s.directions));
  if (s.texels < k_min_texels || s.texels > k_max_texels)
    throw InputError("texels", "R must be in [" + std::to_string(k_min_texels) + ", " +
                                   std::to_string(k_max_texels) + "], got " +
                                   std::to_string(s.texels));
  if (s.spp < k_min_bake_spp || s.spp > k_max_bake_spp)
    throw InputError("spp", "must be in [" + std::to_string(k_min_bake_spp) + ", " +
                                std::to_string(k_max_bake_spp) + "], got " + std::to_string(s.spp));
  if (!(s.texels_per_pixel > 0.0f) || s.texels_per_pixel > k_max_texels_per_pixel)
    throw InputError("texels_per_pixel", "must be in (0, 64]");
  if (s.shard_count < 1 || s.shard_index < 0 || s.shard_index >= s.shard_count)
    throw InputError("shard", "part " + std::to_string(s.shard_index + 1) + " of " +
                                  std::to_string(s.shard_count) + " does not exist");
}

/// The view direction, in the quad's frame, that `node` is baked from.
V3f node_to_eye(const DirectionGrid& dirs, int node) {
  const int side = node / dirs.nodes_per_side();
  const int rem = node % dirs.nodes_per_side();
  return dirs.bake_direction(side, rem % dirs.k, rem / dirs.k);
}

/// One march sample: a jittered point of texel (a, b)'s footprint toward
/// `to_eye_local`, seeded by its own indices so that the result does not
/// depend on scheduling. run_bake and the probe both go through here.
MarchResult bake_sample(const ClothScene& prepared, const BakeSample& x, int size,
                        const V3f& to_eye_local, uint64_t seed) {
  Rng rng(hash_key(seed, x.object, uint64_t(x.quad), uint64_t(x.a), uint64_t(x.b), uint64_t(x.node),
                   uint64_t(x.k)));
  const float ps = (x.a + rng.next_float()) / size;
  const float pt = 1.0f - (x.b + rng.next_float()) / size;
  const SurfaceFrame f = prepared.patch(x.object, x.quad).frame(ps, pt);
  return prepared.shade_surface(x.object, x.quad, ps, pt, -f.world_from_local(to_eye_local), rng);
}

/// Appends the samples of quad q whose indices in the plan's sequence (the
/// quad's run starting at `begin`) are in `wanted` (sorted) from `next` on;
/// returns the length of the quad's run.
uint64_t locate_in_quad(const LookupTable& t, int o, int q, int spp, uint64_t begin,
                        const std::vector<uint64_t>& wanted, size_t& next,
                        std::vector<BakeSample>& out) {
  const uint64_t size = uint64_t(t.sizes[q]);
  const uint64_t per_node = size * size * uint64_t(spp);
  std::vector<int> nodes;  // the quad's baked nodes, in ascending order
  for (int n = 0; n < t.node_count(); ++n)
    if (t.is_baked(q, n)) nodes.push_back(n);
  const uint64_t end = begin + per_node * nodes.size();
  for (; next < wanted.size() && wanted[next] < end; ++next) {
    const uint64_t i = wanted[next] - begin;
    const uint64_t texel = (i % per_node) / uint64_t(spp);
    out.push_back({o, q, nodes[size_t(i / per_node)], int(texel % size), int(texel / size),
                   int(i % uint64_t(spp))});
  }
  return end - begin;
}

/// An adaptive bake's plan for one quad: marks in `flags` the direction
/// nodes the camera's views of it read, and returns its texels per side from
/// its projected size (0 when the camera does not see it).
int plan_adaptive_quad(const QuadPatch& patch, const PinholeCamera& cam, const DirectionGrid& dirs,
                       const BakeSettings& s, uint8_t* flags) {
  // Directions: where the camera sees the quad from, on a 33 x 33 grid
  // of patch points (dense enough that no view direction between two
  // of them falls into a direction cell neither reads); each marks the
  // four nodes its lookup interpolates.
  bool seen = false;
  constexpr int n = 32;
  for (int b = 0; b <= n; ++b)
    for (int a = 0; a <= n; ++a) {
      const float ps = float(a) / n, pt = float(b) / n;
      const V3f p = patch.position_world(ps, pt);
      float x, y;
      if (!cam.project(p, x, y)) continue;
      const float margin = 2.0f;
      if (x < -margin || y < -margin || x > cam.width + margin || y > cam.height + margin) continue;
      seen = true;
      const SurfaceFrame f = patch.frame(ps, pt);
      const V3f to_eye = (cam.position_world - p).normalized();
      const DirectionGrid::Footprint fp = dirs.locate(f.local_from_world(to_eye));
      for (int j : {fp.j0, fp.j1})
        for (int i : {fp.i0, fp.i1}) flags[dirs.node_index(fp.side, i, j)] = 1;
    }
  if (!seen) return 0;
  // Texels: the longest projected edge, in pixels, times texels per pixel.
  float longest = 0.0f;
  bool all_projected = true;
  V3f corners[4];
  float px[4], py[4];
  for (int c = 0; c < 4; ++c) {
    corners[c] = patch.corner_world(c);
    all_projected = all_projected && cam.project(corners[c], px[c], py[c]);
  }
  if (all_projected)
    for (int c = 0; c < 4; ++c) {
      const int d = (c + 1) % 4;
      longest = std::max(longest, std::hypot(px[d] - px[c], py[d] - py[c]));
    }
  else
    longest = float(std::max(cam.width, cam.height));
  return std::clamp(int(std::ceil(longest * s.texels_per_pixel / 4.0f)) * 4, s.min_texels,
                    s.max_texels);
}

}  // namespace

BakePlan plan_bake(const ClothScene& prepared, const BakeSettings& s) {
  check_settings(s);
  const Scene& scene = prepared.scene();
  const PinholeCamera& cam = scene.camera;
  BakePlan plan;
  for (int o = 0; o < prepared.object_count(); ++o) {
    LookupTable t;
    t.dirs.k = s.directions;
    t.dirs.map = s.map;
    const int n_quads = prepared.quad_count(o);
    const int nodes = 2 * s.directions * s.directions;
    t.sizes.assign(n_quads, 0);
    // `wanted`: what the whole bake computes (it fixes the layout, so that
    // partial bakes share it); `t.baked`: what this bake computes.
    std::vector<uint8_t> wanted(size_t(n_quads) * nodes, 0);
    const int end = s.quad_end < 0 ? n_quads : std::min(s.quad_end, n_quads);
    if (s.quad_begin < 0 || s.quad_begin > n_quads || s.quad_begin >= end)
      throw InputError("quads", "the range " + std::to_string(s.quad_begin) + "-" +
                                    std::to_string(s.quad_end - 1) + " selects no quad of the " +
                                    std::to_string(n_quads) + " (numbered 0-" +
                                    std::to_string(n_quads - 1) + ")");
    const auto outside = [&](int q) {
      return q < s.quad_begin || q >= end || q % s.shard_count != s.shard_index;
    };
    for (int q = 0; q < n_quads; ++q) {
      const QuadPatch& patch = prepared.patch(o, q);
      plan.full_nodes += nodes;
      plan.full_texels += uint64_t(s.texels) * s.texels;
      if (!patch.valid()) continue;
      uint8_t* flags = &wanted[size_t(q) * nodes];
      int size = s.texels;
      if (!s.adaptive) {
        std::fill(flags, flags + nodes, 1);
      } else {
        size = plan_adaptive_quad(patch, cam, t.dirs, s, flags);
        if (size == 0) continue;  // the camera does not see it
      }
      // The layout covers every quad the whole bake would, so partial bakes
      // (--quads) of one scene share it and merge into the whole bake; only
      // the flags are limited to the subset.
      t.sizes[q] = size;
      if (outside(q)) continue;
      int baked_nodes = 0;
      for (int n = 0; n < nodes; ++n) baked_nodes += flags[n];
      plan.baked_nodes += baked_nodes;
      plan.texels += uint64_t(size) * size;
      plan.texel_direction_samples += uint64_t(size) * size * baked_nodes * s.spp;
    }
    plan.full_texel_direction_samples +=
        uint64_t(n_quads) * s.texels * s.texels * nodes * uint64_t(s.spp);
    t.pack(wanted);
    t.baked = wanted;
    for (int q = 0; q < n_quads; ++q)
      if (outside(q))
        std::fill_n(t.baked.begin() + ptrdiff_t(q) * nodes, nodes, uint8_t(0));
    plan.objects.push_back(std::move(t));
  }
  return plan;
}

std::vector<LookupTable> run_bake(ClothScene& prepared, const BakePlan& plan, const BakeSettings& s,
                                  const std::function<void(double)>& progress) {
  prepared.prepare_light_caches();
  std::vector<LookupTable> tables = plan.objects;
  std::atomic<uint64_t> done{0};
  std::mutex progress_mutex;
  int last_percent = -1;
  const double total = double(std::max<uint64_t>(1, plan.texel_direction_samples));
  for (size_t o = 0; o < tables.size(); ++o) {
    LookupTable& t = tables[o];
    t.allocate_atlases();
    const int nodes = t.node_count();
    // One job per (quad, texel row): every texel's samples are seeded by
    // their own indices, so the result does not depend on scheduling.
    std::vector<std::pair<int, int>> jobs;
    for (int q = 0; q < t.quad_count(); ++q)
      if (t.quad_baked(q))
        for (int b = 0; b < t.sizes[q]; ++b) jobs.emplace_back(q, b);
    tbb::parallel_for(size_t(0), jobs.size(), [&](size_t job) {
      const auto [q, b] = jobs[job];
      const int size = t.sizes[q];
      uint64_t local = 0;
      for (int a = 0; a < size; ++a)
        for (int node = 0; node < nodes; ++node) {
          if (!t.is_baked(q, node)) continue;
          const V3f to_eye_local = node_to_eye(t.dirs, node);
          float sum[4] = {0, 0, 0, 0};
          for (int k = 0; k < s.spp; ++k) {
            const MarchResult m =
                bake_sample(prepared, {int(o), q, node, a, b, k}, size, to_eye_local, s.seed);
            sum[0] += m.radiance.x;
            sum[1] += m.radiance.y;
            sum[2] += m.radiance.z;
            sum[3] += 1.0f - m.transmittance;
          }
          Imath::half* texel = t.texel(q, node, a, b);
          for (int c = 0; c < 4; ++c) texel[c] = Imath::half(sum[c] / float(s.spp));
          local += uint64_t(s.spp);
        }
      const uint64_t now = done += local;
      if (progress) {
        const int percent = int(100.0 * double(now) / total);
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (percent != last_percent) {
          last_percent = percent;
          progress(double(now) / total);
        }
      }
    });
    t.fill_gutters();
  }
  return tables;
}

std::vector<BakeSample> probe_samples(const BakePlan& plan, const BakeSettings& s, uint64_t n) {
  const uint64_t total = plan.texel_direction_samples;
  n = std::min(n, total);
  // One index per equal run of the sequence, at a hashed offset inside it.
  std::vector<uint64_t> wanted(n);
  for (uint64_t j = 0; j < n; ++j) {
    const double u = unit_double(hash_key(s.seed, rng_stream::probe, j));
    const uint64_t lo = uint64_t(double(j) * double(total) / double(n));
    const uint64_t hi = uint64_t(double(j + 1) * double(total) / double(n));
    wanted[j] = std::min(total - 1, lo + uint64_t(u * double(std::max<uint64_t>(1, hi - lo))));
  }
  std::sort(wanted.begin(), wanted.end());  // rounding could swap neighbours
  std::vector<BakeSample> out;
  out.reserve(n);
  size_t next = 0;
  uint64_t begin = 0;
  for (size_t o = 0; o < plan.objects.size(); ++o) {
    const LookupTable& t = plan.objects[o];
    for (int q = 0; q < t.quad_count() && next < n; ++q)
      if (t.quad_baked(q)) begin += locate_in_quad(t, int(o), q, s.spp, begin, wanted, next, out);
  }
  return out;
}

std::vector<MarchResult> evaluate_bake_samples(ClothScene& prepared, const BakePlan& plan,
                                               const BakeSettings& s,
                                               const std::vector<BakeSample>& samples) {
  prepared.prepare_light_caches();
  std::vector<MarchResult> out(samples.size());
  tbb::parallel_for(size_t(0), samples.size(), [&](size_t i) {
    const BakeSample& x = samples[i];
    const LookupTable& t = plan.objects[size_t(x.object)];
    out[i] = bake_sample(prepared, x, t.sizes[x.quad], node_to_eye(t.dirs, x.node), s.seed);
  });
  return out;
}

uint64_t probe_bake(ClothScene& prepared, const BakePlan& plan, const BakeSettings& s, uint64_t n) {
  return evaluate_bake_samples(prepared, plan, s, probe_samples(plan, s, n)).size();
}

SurfaceShader lookup_shader(const ClothScene& prepared, const std::vector<LookupTable>& tables,
                            std::atomic<uint64_t>* misses) {
  return
      [&prepared, &tables, misses](int o, int q, float s, float t, const V3f& ray_dir_world, Rng&) {
        MarchResult m;
        const SurfaceFrame f = prepared.patch(o, q).frame(s, t);
        float rgba[4];
        if (size_t(o) >= tables.size() ||
            !tables[o].sample(q, s, t, f.local_from_world(-ray_dir_world), rgba)) {
          if (misses) ++*misses;
          return m;  // not baked: transparent
        }
        m.radiance = V3f(rgba[0], rgba[1], rgba[2]);
        m.transmittance = std::clamp(1.0f - rgba[3], 0.0f, 1.0f);
        return m;
      };
}

}  // namespace clothbake
