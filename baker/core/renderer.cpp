#include "core/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/cell_walk.h"
#include "core/error.h"
#include "core/random.h"
#include "core/volume_generator.h"
#include "core/volume_march.h"

namespace clothbake {

namespace {
using Imath::V3f;
constexpr int k_bin_px = 16;      // screen tile size for camera-ray binning
constexpr int k_max_layers = 16;  // cloth layers one ray may cross
constexpr float k_cap_repeats = 64.0f;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
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

struct Renderer::Object {
  const ClothObject* source = nullptr;
  std::shared_ptr<const VolumeTexture> volume;
  std::unique_ptr<FiberShader> shader;
  std::vector<QuadPatch> patches;
  std::vector<TransmittanceCache> caches;  // [quad * lights + light], Cached mode
};

Renderer::Renderer(const Scene& scene, uint64_t memory_budget_bytes,
                   std::vector<std::shared_ptr<const VolumeTexture>> volumes)
    : m_scene(scene) {
  const auto t0 = std::chrono::steady_clock::now();
  const RenderSettings& rs = scene.settings;
  m_objects.resize(scene.objects.size());
  for (size_t o = 0; o < scene.objects.size(); ++o) {
    const ClothObject& src = scene.objects[o];
    Object& obj = m_objects[o];
    obj.source = &src;
    if (o < volumes.size() && volumes[o])
      obj.volume = volumes[o];
    else if (src.volume)
      obj.volume = src.volume;
    else
      obj.volume =
          std::make_shared<const VolumeTexture>(generate_volume(src.cloth, memory_budget_bytes));
    obj.shader = std::make_unique<FiberShader>(rs.fiber_model, src.cloth.shading.fiber_aspect,
                                               src.cloth.shading.exponent, rs.fiber_samples,
                                               hash_key(rs.seed, 0x7461626c65ull, o));
    const V3f size = obj.volume->size_mm();
    obj.patches.reserve(src.mesh.quads.size());
    for (size_t q = 0; q < src.mesh.quads.size(); ++q)
      obj.patches.emplace_back(src.mesh, int(q), src.repeats_per_uv, Imath::V2f(size.x, size.y),
                               size.z, src.thickness_world);
  }
  build_bins();
  m_stats.setup_seconds = seconds_since(t0);
}

Renderer::~Renderer() = default;

const VolumeTexture& Renderer::volume(int object) const { return *m_objects[object].volume; }
int Renderer::object_count() const { return int(m_objects.size()); }
int Renderer::quad_count(int object) const { return int(m_objects[object].patches.size()); }

const QuadPatch& Renderer::patch(int object, int quad) const {
  return m_objects[object].patches[quad];
}

void Renderer::build_bins() {
  const PinholeCamera& cam = m_scene.camera;
  m_bins_x = (cam.width + k_bin_px - 1) / k_bin_px;
  m_bins_y = (cam.height + k_bin_px - 1) / k_bin_px;
  m_bins.assign(size_t(m_bins_x) * m_bins_y, {});
  for (size_t o = 0; o < m_objects.size(); ++o)
    for (size_t q = 0; q < m_objects[o].patches.size(); ++q) {
      const QuadPatch& patch = m_objects[o].patches[q];
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
        for (int bx = bx0; bx <= bx1; ++bx)
          m_bins[size_t(by) * m_bins_x + bx].emplace_back(int(o), int(q));
    }
}

void Renderer::prepare_light_caches() {
  if (m_caches_ready || m_scene.settings.transmittance != TransmittanceMode::Cached) return;
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n_lights = m_scene.lights.size();
  for (Object& obj : m_objects) {
    obj.caches.assign(obj.patches.size() * n_lights, {});
    // One cache per quad and light, for the light direction at the quad's
    // centre carried into its texture frame.
    tbb::parallel_for(size_t(0), obj.patches.size() * n_lights, [&](size_t job) {
      const size_t q = job / n_lights, l = job % n_lights;
      const QuadPatch& patch = obj.patches[q];
      if (!patch.valid()) return;
      const SurfaceFrame frame = patch.frame(0.5f, 0.5f);
      V3f to_light_world, irradiance;
      m_scene.lights[l].illuminate(patch.position_world(0.5f, 0.5f), to_light_world, irradiance);
      const V3f to_light_texture = frame.texture_from_world(to_light_world).normalized();
      obj.caches[job] =
          TransmittanceCache::build(*obj.volume, to_light_texture, obj.source->extinction_per_mm);
    });
  }
  m_caches_ready = true;
  m_stats.setup_seconds += seconds_since(t0);
}

bool Renderer::nearest_hit(const Ray& ray, float t_min, int& object, int& quad, PatchHit& hit,
                           int bin) const {
  float t_max = 1e30f;
  bool found = false;
  auto test = [&](int o, int q) {
    PatchHit h;
    if (m_objects[o].patches[q].intersect(ray, t_min, t_max, h)) {
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
    for (size_t o = 0; o < m_objects.size(); ++o)
      for (size_t q = 0; q < m_objects[o].patches.size(); ++q)
        if (m_objects[o].patches[q].valid()) test(int(o), int(q));
  }
  return found;
}

TraceResult Renderer::trace(const Ray& ray_world, uint64_t seed) const {
  return trace_binned(ray_world, seed, -1, nullptr);
}

MarchResult Renderer::shade_surface(int o, int q, float s, float t, const V3f& ray_dir_world,
                                    Rng& rng) const {
  const RenderSettings& rs = m_scene.settings;
  const Object& obj = m_objects[o];
  const QuadPatch& patch = obj.patches[q];
  const VolumeTexture& volume = *obj.volume;

  // The map m: hit point, view and lights carried into texture space.
  const SurfaceFrame frame = patch.frame(s, t);
  const V3f p_world = patch.position_world(s, t);
  const V3f dir_texture = frame.texture_from_world(ray_dir_world).normalized();
  const V3f top_texture = patch.texture_point(s, t);
  const float cap = k_cap_repeats * std::max(volume.size_mm().x, volume.size_mm().y);
  V3f entry_texture = top_texture;
  float length_mm = 0.0f;
  if (dir_texture.z < 0.0f) {  // from the front: down from the top face
    length_mm = distance_to_exit(volume, top_texture, dir_texture, cap);
  } else if (dir_texture.z > 0.0f) {  // from behind: up from the bottom face to the hit
    length_mm = std::min(cap, volume.size_mm().z / dir_texture.z);
    entry_texture = top_texture - dir_texture * length_mm;
    // A grazing view from behind (within ~0.3 degrees of the horizon) is capped:
    // the march must still start at the bottom face, the side the eye sees, not
    // `cap` before the hit inside the volume, nearer the lit top (that was up to
    // 5.8 x too bright, tests/core/stability_test.cpp). Only the far end is cut.
    entry_texture.z = 0.0f;
  }
  // Draw the random numbers whether or not the march runs, so one ray's
  // sequence does not depend on another's geometry.
  const float jitter = rng.next_float();
  const uint64_t seed = rng.next_u64();
  if (length_mm <= 0.0f) return MarchResult{};

  MarchLight lights[k_max_march_lights];
  const size_t n_lights = std::min(m_scene.lights.size(), k_max_march_lights);
  for (size_t l = 0; l < n_lights; ++l) {
    V3f to_light_world;
    m_scene.lights[l].illuminate(p_world, to_light_world, lights[l].irradiance);
    lights[l].to_light_local =
        V3f(to_light_world.dot(frame.tangent_world), to_light_world.dot(frame.bitangent_world),
            to_light_world.dot(frame.normal_world));
    lights[l].to_light_texture = frame.texture_from_world(to_light_world).normalized();
    lights[l].cache = nullptr;
    if (rs.transmittance == TransmittanceMode::Cached && !obj.caches.empty()) {
      const TransmittanceCache& cache = obj.caches[size_t(q) * m_scene.lights.size() + l];
      lights[l].cache_depth_scale = cache.depth_scale_for(lights[l].to_light_texture);
      // A light on the other side of the cloth here than at the quad's
      // centre: march for this hit.
      if (lights[l].cache_depth_scale > 0.0f) lights[l].cache = &cache;
    }
  }
  const V3f to_eye_world = -ray_dir_world;
  MarchInput in;
  in.volume = &volume;
  in.shader = obj.shader.get();
  in.entry_texture = entry_texture;
  in.dir_texture = dir_texture;
  in.length_mm = length_mm;
  in.to_eye_local =
      V3f(to_eye_world.dot(frame.tangent_world), to_eye_world.dot(frame.bitangent_world),
          to_eye_world.dot(frame.normal_world));
  in.mm_per_world = frame.mm_per_world;
  in.lights = std::span<const MarchLight>(lights, n_lights);
  in.extinction_per_mm = obj.source->extinction_per_mm;
  const V3f cell = volume.cell_size_mm();
  in.step_mm = rs.step_cells * std::min({cell.x, cell.y, cell.z});
  in.cutoff = rs.cutoff;
  in.jitter = jitter;
  in.shading = rs.shading;
  in.isotropic_albedo = obj.source->isotropic_albedo;
  in.seed = seed;
  in.roulette = rs.light_roulette;
  return march_view_ray(in);
}

TraceResult Renderer::trace_binned(const Ray& ray, uint64_t seed, int bin,
                                   const HitShader* shader) const {
  TraceResult out;
  const RenderSettings& rs = m_scene.settings;
  Rng rng(seed);
  float t_min = 1e-6f;
  float throughput = 1.0f;
  for (int layer = 0; layer < k_max_layers && throughput > rs.cutoff; ++layer) {
    int o = -1, q = -1;
    PatchHit hit;
    if (!nearest_hit(ray, t_min, o, q, hit, bin)) break;
    // Where the ray leaves the volume below a front-facing hit: the next
    // layer can only start beyond it.
    const Object& obj = m_objects[o];
    const SurfaceFrame frame = obj.patches[q].frame(hit.s, hit.t);
    const V3f dir_scaled = frame.texture_from_world(ray.direction_world);  // mm per world unit
    float world_after = 0.0f;
    if (dir_scaled.z < 0.0f) {
      const VolumeTexture& volume = *obj.volume;
      const float cap = k_cap_repeats * std::max(volume.size_mm().x, volume.size_mm().y);
      const V3f dir_texture = dir_scaled.normalized();
      world_after =
          distance_to_exit(volume, obj.patches[q].texture_point(hit.s, hit.t), dir_texture, cap) /
          dir_scaled.length();
    }
    t_min = hit.t_world + world_after + 1e-5f * std::max(1.0f, hit.t_world);
    const MarchResult m = shader ? (*shader)(o, q, hit.s, hit.t, ray.direction_world, rng)
                                 : shade_surface(o, q, hit.s, hit.t, ray.direction_world, rng);
    out.radiance += m.radiance * throughput;
    throughput *= m.transmittance;
    out.samples += uint64_t(m.samples);
  }
  out.transmittance = throughput < rs.cutoff ? 0.0f : throughput;
  return out;
}

Image Renderer::render(const std::function<void(double)>& progress) {
  prepare_light_caches();
  return render_with(nullptr, progress);
}

Image Renderer::render_with(const HitShader* shader, const std::function<void(double)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const PinholeCamera& cam = m_scene.camera;
  const RenderSettings& rs = m_scene.settings;
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
          sum += r.radiance + m_scene.background * r.transmittance;
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
