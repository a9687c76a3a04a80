#include "core/scene/cloth_scene.h"

#include <algorithm>
#include <chrono>

#include <tbb/parallel_for.h>

#include "core/march/cell_walk.h"
#include "core/texture/volume_generator.h"
#include "core/util/stopwatch.h"
#include "core/weave/cloth_colours.h"

namespace clothbake {

namespace {
using Imath::V3f;
}  // namespace

struct ClothScene::Object {
  const ClothObject* source = nullptr;
  std::shared_ptr<const VolumeTexture> volume;
  std::unique_ptr<FiberShader> shader;
  std::vector<QuadPatch> patches;
  std::vector<TransmittanceCache> caches;  // [quad * lights + light], Cached mode
};

ClothScene::ClothScene(const Scene& scene, uint64_t memory_budget_bytes,
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
    obj.shader = make_object_fiber_shader(rs.fiber_model, src.cloth.shading.fiber_aspect,
                                          src.cloth.shading.exponent, rs.fiber_samples, rs.seed,
                                          o);
    // repeats_per_uv counts repeats of the weave, not of its colour sequence:
    // colours never change the cloth's size (a stripe of 3 ends on a plain
    // weave keeps the threads where the plain weave has them).
    const V3f size = obj.volume->size_mm();
    const Imath::V2f repeat_mm =
        src.volume ? Imath::V2f(size.x, size.y) : weave_repeat_mm(src.cloth);
    obj.patches.reserve(src.mesh.quads.size());
    for (size_t q = 0; q < src.mesh.quads.size(); ++q)
      obj.patches.emplace_back(src.mesh, int(q), src.repeats_per_uv, repeat_mm, size.z,
                               src.thickness_world);
  }
  m_setup_seconds = seconds_since(t0);
}

ClothScene::~ClothScene() = default;

const VolumeTexture& ClothScene::volume(int object) const { return *m_objects[object].volume; }
int ClothScene::object_count() const { return int(m_objects.size()); }
int ClothScene::quad_count(int object) const { return int(m_objects[object].patches.size()); }
const QuadPatch& ClothScene::patch(int object, int quad) const {
  return m_objects[object].patches[quad];
}

void ClothScene::prepare_light_caches() {
  if (m_caches_ready || m_scene.settings.transmittance != TransmittanceMode::Cached) return;
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n_lights = m_scene.lights.size();
  for (Object& obj : m_objects) {
    obj.caches.assign(obj.patches.size() * n_lights, {});
    // One cache per quad and light, for the light direction at the quad's
    // centre carried into its texture frame. A sampled (area) light's
    // direction changes with every sample: it marches, and has no cache.
    tbb::parallel_for(size_t(0), obj.patches.size() * n_lights, [&](size_t job) {
      const size_t q = job / n_lights, l = job % n_lights;
      const QuadPatch& patch = obj.patches[q];
      if (!patch.valid() || m_scene.lights[l].sampled()) return;
      const SurfaceFrame frame = patch.frame(0.5f, 0.5f);
      V3f to_light_world, irradiance;
      m_scene.lights[l].illuminate(patch.position_world(0.5f, 0.5f), to_light_world, irradiance);
      const V3f to_light_texture = frame.texture_from_world(to_light_world).normalized();
      obj.caches[job] =
          TransmittanceCache::build(*obj.volume, to_light_texture, obj.source->extinction_per_mm);
    });
  }
  m_caches_ready = true;
  m_setup_seconds += seconds_since(t0);
}

float ClothScene::world_distance_below(int o, int q, float s, float t,
                                       const V3f& ray_dir_world) const {
  const Object& obj = m_objects[o];
  const QuadPatch& patch = obj.patches[q];
  const V3f dir_scaled = patch.frame(s, t).texture_from_world(ray_dir_world);  // mm per world unit
  if (!(dir_scaled.z < 0.0f)) return 0.0f;
  const VolumeTexture& volume = *obj.volume;
  const V3f dir_texture = dir_scaled.normalized();
  return distance_to_exit(volume, patch.texture_point(s, t), dir_texture, march_cap_mm(volume)) /
         dir_scaled.length();
}

MarchResult ClothScene::shade_surface(int o, int q, float s, float t, const V3f& ray_dir_world,
                                      Rng& rng) const {
  const RenderSettings& rs = m_scene.settings;
  const Object& obj = m_objects[o];
  const QuadPatch& patch = obj.patches[q];
  const VolumeTexture& volume = *obj.volume;

  // The map m: hit point, view and lights carried into texture space.
  const SurfaceFrame frame = patch.frame(s, t);
  const V3f p_world = patch.position_world(s, t);
  const V3f dir_texture = frame.texture_from_world(ray_dir_world).normalized();
  const SlabEntry slab = slab_entry(volume, patch.texture_point(s, t), dir_texture);
  // Draw the random numbers whether or not the march runs, so one ray's
  // sequence does not depend on another's geometry.
  const float jitter = rng.next_float();
  const uint64_t seed = rng.next_u64();
  // One point of each area light per hit (drawn only for area lights, so a
  // scene without them draws what it always drew); a pixel's samples
  // integrate the light.
  const size_t n_lights = std::min(m_scene.lights.size(), k_max_march_lights);
  Imath::V2f light_points[k_max_march_lights];
  for (size_t l = 0; l < n_lights; ++l)
    if (m_scene.lights[l].sampled()) {
      light_points[l].x = rng.next_float();
      light_points[l].y = rng.next_float();
    }
  if (slab.length_mm <= 0.0f) return MarchResult{};

  MarchLight lights[k_max_march_lights];
  for (size_t l = 0; l < n_lights; ++l) {
    const Light& light = m_scene.lights[l];
    V3f to_light_world;
    light.illuminate(p_world, to_light_world, lights[l].irradiance, light_points[l].x,
                     light_points[l].y);
    lights[l].to_light_local = frame.local_from_world(to_light_world);
    lights[l].to_light_texture = frame.texture_from_world(to_light_world).normalized();
    lights[l].cache = nullptr;
    if (rs.transmittance == TransmittanceMode::Cached && !obj.caches.empty() &&
        !light.sampled()) {
      const TransmittanceCache& cache = obj.caches[size_t(q) * m_scene.lights.size() + l];
      lights[l].cache_depth_scale = cache.depth_scale_for(lights[l].to_light_texture);
      // A light on the other side of the cloth here than at the quad's
      // centre: march for this hit.
      if (lights[l].cache_depth_scale > 0.0f) lights[l].cache = &cache;
    }
  }
  MarchInput in;
  in.volume = &volume;
  in.shader = obj.shader.get();
  in.entry_texture = slab.entry_texture;
  in.dir_texture = dir_texture;
  in.length_mm = slab.length_mm;
  in.to_eye_local = frame.local_from_world(-ray_dir_world);
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

}  // namespace clothbake
