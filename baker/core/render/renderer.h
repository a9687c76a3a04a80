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

#include "core/geometry/quad_patch.h"
#include "core/march/volume_march.h"
#include "core/scene/cloth_scene.h"
#include "core/scene/scene.h"
#include "core/texture/volume_texture.h"
#include "core/util/image.h"
#include "core/util/random.h"

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

/// The pixel loop over a prepared scene: camera rays binned by screen tile,
/// each traced through every cloth layer it crosses, shaded by the prepared
/// scene's march (or a substitute shader), composited over the background.
class Renderer {
 public:
  using HitShader = SurfaceShader;

  /// Renders `prepared`, which must outlive the renderer.
  explicit Renderer(ClothScene& prepared);
  /// Prepares the scene itself (ClothScene's constructor) and renders it:
  /// for callers that need nothing else of it.
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

  const RenderStats& stats() const { return m_stats; }
  const Scene& scene() const { return m_prepared.scene(); }
  ClothScene& prepared() { return m_prepared; }
  const ClothScene& prepared() const { return m_prepared; }

 private:
  bool nearest_hit(const Ray& ray, float t_min, int& object, int& quad, PatchHit& hit,
                   int bin) const;
  TraceResult trace_binned(const Ray& ray_world, uint64_t seed, int bin,
                           const HitShader* shader) const;
  void build_bins();

  explicit Renderer(std::unique_ptr<ClothScene> owned);  // renders and keeps `owned`

  std::unique_ptr<ClothScene> m_owned;  // set by the second constructor only
  ClothScene& m_prepared;
  // Screen-space bins of quads for camera rays: tile -> (object, quad) list.
  int m_bins_x = 0, m_bins_y = 0;
  std::vector<std::vector<std::pair<int, int>>> m_bins;
  double m_bins_seconds = 0.0;
  RenderStats m_stats;
};

}  // namespace clothbake
