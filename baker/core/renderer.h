#pragma once
/// The reference renderer: Kimoto & Ohno's algorithm (PAPER.md s.4-5) over a
/// whole scene. A camera ray meets a quad of a cloth mesh; the map m carries
/// the hit, the view and the lights into texture space; the view ray is
/// marched through the volume texture; what the cloth lets through continues
/// to the next quad and finally to the background.
///
/// Image: linear RGB radiance, box filter over each pixel with `spp`
/// stratified jittered samples; alpha = coverage x (1 - see-through).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/fiber_shader.h"
#include "core/image.h"
#include "core/light_transmittance.h"
#include "core/quad_patch.h"
#include "core/random.h"
#include "core/scene.h"
#include "core/volume_march.h"
#include "core/volume_texture.h"

namespace clothbake {

struct RenderStats {
  double setup_seconds = 0.0;   ///< volumes, fibre tables, light caches
  double render_seconds = 0.0;  ///< the pixel loop
  uint64_t camera_rays = 0;     ///< pixel samples traced
  uint64_t march_samples = 0;   ///< shaded samples over all marches
};

/// What one ray sees through all the cloth layers it crosses.
struct TraceResult {
  Imath::V3f radiance{0, 0, 0};  ///< cloth radiance, background not included
  float transmittance = 1.0f;    ///< fraction of the background that shows through
  uint64_t samples = 0;
};

/// Bytes a render of `camera` holds at its peak: the float RGBA image and the
/// float copy the EXR writer makes of it (32 bytes per pixel).
uint64_t render_image_bytes(const PinholeCamera& camera);

/// Refuses, before anything is allocated, a camera whose image would not fit
/// `memory_budget_bytes`: InputError on "camera.resolution" with the estimate.
void check_render_memory(const PinholeCamera& camera, uint64_t memory_budget_bytes);

class Renderer {
 public:
  /// Computes what one cloth surface point shows along a ray: by default the
  /// march (shade_surface); lookup-render substitutes a baked lookup.
  using HitShader = std::function<MarchResult(int object, int quad, float s, float t,
                                              const Imath::V3f& ray_dir_world, Rng& rng)>;

  /// Prepares every object: its volume texture (the object's `volume` if
  /// set, else generated from its cloth spec and refused over the memory
  /// budget), its fibre shader and its quad patches. `volumes`, if given,
  /// replaces the volume of each object (tests, bakes reusing one).
  Renderer(const Scene& scene, uint64_t memory_budget_bytes,
           std::vector<std::shared_ptr<const VolumeTexture>> volumes = {});
  ~Renderer();

  /// Renders the scene's camera. `progress(fraction)` is called from worker
  /// threads, serialised, at most once per percent.
  Image render(const std::function<void(double)>& progress = {});

  /// Traces one world-space ray through the cloth (all objects, all layers).
  /// `seed` drives the march jitter and the direct fibre model.
  TraceResult trace(const Ray& ray_world, uint64_t seed) const;

  /// Renders with a substitute per-hit shader (same sampling, seeds, layers
  /// and compositing as render()).
  Image render_with(const HitShader* shader, const std::function<void(double)>& progress = {});

  /// The march at patch parameters (s, t) of a quad, for a ray arriving in
  /// direction `ray_dir_world` (front or back side): radiance and see-through
  /// of that one layer. Draws exactly two random numbers from `rng`.
  MarchResult shade_surface(int object, int quad, float s, float t, const Imath::V3f& ray_dir_world,
                            Rng& rng) const;
  int object_count() const;
  int quad_count(int object) const;

  const RenderStats& stats() const { return m_stats; }
  const Scene& scene() const { return m_scene; }
  const VolumeTexture& volume(int object) const;
  const QuadPatch& patch(int object, int quad) const;
  /// Builds the light caches (Cached mode) for every valid quad; render()
  /// calls it; the baker may call it for a subset.
  void prepare_light_caches();

 private:
  struct Object;
  bool nearest_hit(const Ray& ray, float t_min, int& object, int& quad, PatchHit& hit,
                   int bin) const;
  TraceResult trace_binned(const Ray& ray_world, uint64_t seed, int bin,
                           const HitShader* shader) const;
  void build_bins();

  const Scene& m_scene;
  std::vector<Object> m_objects;
  // Screen-space bins of quads for camera rays: tile -> (object, quad) list.
  int m_bins_x = 0, m_bins_y = 0;
  std::vector<std::vector<std::pair<int, int>>> m_bins;
  bool m_caches_ready = false;
  RenderStats m_stats;
};

}  // namespace clothbake
