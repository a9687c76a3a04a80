#include "core/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/march/volume_march.h"
#include "core/util/error.h"
#include "core/util/stopwatch.h"
#include "core/util/random.h"

namespace clothbake {

namespace {
using Imath::V3f;
constexpr int k_bin_px = 16;      // screen tile size for camera-ray binning
constexpr int k_max_layers = 16;  // cloth layers one ray may cross
}  // namespace

uint64_t render_image_bytes(const PinholeCamera& camera) {
  return uint64_t(std::max(0, camera.width)) * uint64_t(std::max(0, camera.height)) * 2 * 4 *
         sizeof(float);
}

void check_render_memory(const PinholeCamera& camera, uint64_t memory_budget_bytes) {
  const uint64_t need = render_image_bytes(camera);
  if (need > memory_budget_bytes)
    throw InputError("camera.resolution",
                     std::to_string(camera.width) + " x " + std::to_string(camera.height) +
                         " pixels need an estimated " + std::to_string(need >> 20) +
                         " MiB for the image and its copy for writing, over the memory budget "
                         "of " +
                         std::to_string(memory_budget_bytes >> 20) + " MiB; lower the resolution");
}

Renderer::Renderer(ClothScene& prepared) : m_prepared(prepared) {
  const auto t0 = std::chrono::steady_clock::now();
  build_bins();
  m_bins_seconds = seconds_since(t0);
  m_stats.setup_seconds = m_prepared.setup_seconds() + m_bins_seconds;
}

Renderer::Renderer(const Scene& scene, uint64_t memory_budget_bytes,
                   std::vector<std::shared_ptr<const VolumeTexture>> volumes)
    : Renderer(std::make_unique<ClothScene>(scene, memory_budget_bytes, std::move(volumes))) {}

Renderer::Renderer(std::unique_ptr<ClothScene> owned) : Renderer(*owned) {
  m_owned = std::move(owned);
}

Renderer::~Renderer() = default;

void Renderer::build_bins() {
  const PinholeCamera& cam = scene().camera;
  m_bins_x = (cam.width + k_bin_px - 1) / k_bin_px;
  m_bins_y = (cam.height + k_bin_px - 1) / k_bin_px;
  m_bins.assign(size_t(m_bins_x) * m_bins_y, {});
  for (int o = 0; o < m_prepared.object_count(); ++o)
    for (int q = 0; q < m_prepared.quad_count(o); ++q) {
      const QuadPatch& patch = m_prepared.patch(o, q);
      if (!patch.valid()) continue;
      // The patch lies in the convex hull of its corners, so the corners'
      // projections bound it on screen, unless one is behind the camera.
      float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
      bool all_in_front = true;
      for (int c = 0; c < 4; ++c) {
        float x, y;
        if (!cam.project(patch.corner_world(c), x, y)) {
          all_in_front = false;
          break;
        }
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
      }
      int bx0 = 0, by0 = 0, bx1 = m_bins_x - 1, by1 = m_bins_y - 1;
      if (all_in_front) {
        if (x1 < 0 || y1 < 0 || x0 > cam.width || y0 > cam.height) continue;
        bx0 = std::max(0, int(std::floor((x0 - 1) / k_bin_px)));
        by0 = std::max(0, int(std::floor((y0 - 1) / k_bin_px)));
        bx1 = std::min(m_bins_x - 1, int(std::floor((x1 + 1) / k_bin_px)));
        by1 = std::min(m_bins_y - 1, int(std::floor((y1 + 1) / k_bin_px)));
      }
      for (int by = by0; by <= by1; ++by)
        for (int bx = bx0; bx <= bx1; ++bx) m_bins[size_t(by) * m_bins_x + bx].emplace_back(o, q);
    }
}

bool Renderer::nearest_hit(const Ray& ray, float t_min, int& object, int& quad, PatchHit& hit,
                           int bin) const {
  float t_max = 1e30f;
  bool found = false;
  auto test = [&](int o, int q) {
    PatchHit h;
    if (m_prepared.patch(o, q).intersect(ray, t_min, t_max, h)) {
      t_max = h.t_world;
      hit = h;
      object = o;
      quad = q;
      found = true;
    }
  };
  if (bin >= 0) {
    for (const auto& [o, q] : m_bins[bin]) test(o, q);
  } else {
    for (int o = 0; o < m_prepared.object_count(); ++o)
      for (int q = 0; q < m_prepared.quad_count(o); ++q)
        if (m_prepared.patch(o, q).valid()) test(o, q);
  }
  return found;
}

TraceResult Renderer::trace(const Ray& ray_world, uint64_t seed) const {
  return trace_binned(ray_world, seed, -1, nullptr);
}

TraceResult Renderer::trace_binned(const Ray& ray, uint64_t seed, int bin,
                                   const HitShader* shader) const {
  TraceResult out;
  const RenderSettings& rs = scene().settings;
  Rng rng(seed);
  float t_min = 1e-6f;
  float throughput = 1.0f;
  for (int layer = 0; layer < k_max_layers && throughput > rs.cutoff; ++layer) {
    int o = -1, q = -1;
    PatchHit hit;
    if (!nearest_hit(ray, t_min, o, q, hit, bin)) break;
    // Where the ray leaves the volume below a front-facing hit: the next
    // layer can only start beyond it.
    const float world_after =
        m_prepared.world_distance_below(o, q, hit.s, hit.t, ray.direction_world);
    t_min = hit.t_world + world_after + 1e-5f * std::max(1.0f, hit.t_world);
    const MarchResult m =
        shader ? (*shader)(o, q, hit.s, hit.t, ray.direction_world, rng)
               : m_prepared.shade_surface(o, q, hit.s, hit.t, ray.direction_world, rng);
    out.radiance += m.radiance * throughput;
    throughput *= m.transmittance;
    out.samples += uint64_t(m.samples);
  }
  out.transmittance = throughput < rs.cutoff ? 0.0f : throughput;
  return out;
}

Image Renderer::render(const std::function<void(double)>& progress) {
  m_prepared.prepare_light_caches();
  m_stats.setup_seconds = m_prepared.setup_seconds() + m_bins_seconds;
  return render_with(nullptr, progress);
}

Image Renderer::render_with(const HitShader* shader, const std::function<void(double)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const PinholeCamera& cam = scene().camera;
  const RenderSettings& rs = scene().settings;
  Image image(cam.width, cam.height, 4);
  const int strata = std::max(1, int(std::ceil(std::sqrt(double(rs.spp)))));
  std::atomic<int> rows_done{0};
  std::atomic<uint64_t> samples{0};
  std::mutex progress_mutex;
  int last_percent = -1;
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height, 1), [&](const auto& range) {
    uint64_t local_samples = 0;
    for (int py = range.begin(); py != range.end(); ++py) {
      for (int px = 0; px < cam.width; ++px) {
        const int bin = (py / k_bin_px) * m_bins_x + px / k_bin_px;
        V3f sum(0.0f);
        float alpha = 0.0f;
        for (int s = 0; s < rs.spp; ++s) {
          // Stratified jitter over the pixel (box filter).
          Rng rng(hash_key(rs.seed, uint64_t(px), uint64_t(py), uint64_t(s)));
          const float sx = ((s % strata) + rng.next_float()) / strata;
          const float sy = (((s / strata) % strata) + rng.next_float()) / strata;
          const Ray ray = cam.generate_ray(px + sx, py + sy);
          const TraceResult r =
              m_bins[bin].empty() ? TraceResult{} : trace_binned(ray, rng.next_u64(), bin, shader);
          sum += r.radiance + scene().background * r.transmittance;
          alpha += 1.0f - r.transmittance;
          local_samples += r.samples;
        }
        float* p = image.at(px, py);
        const float inv = 1.0f / float(rs.spp);
        p[0] = sum.x * inv;
        p[1] = sum.y * inv;
        p[2] = sum.z * inv;
        p[3] = alpha * inv;
      }
      const int done = ++rows_done;
      if (progress) {
        const int percent = done * 100 / cam.height;
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (percent != last_percent) {
          last_percent = percent;
          progress(double(done) / cam.height);
        }
      }
    }
    samples += local_samples;
  });
  m_stats.render_seconds = seconds_since(t0);
  m_stats.camera_rays = uint64_t(cam.width) * cam.height * rs.spp;
  m_stats.march_samples = samples;
  return image;
}

}  // namespace clothbake
