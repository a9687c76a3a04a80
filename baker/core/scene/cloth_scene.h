#pragma once
/// The scene prepared for marching: per cloth object its volume texture,
/// fibre shader, quad patches (the map m) and light-transmittance caches, and
/// the surface shading that carries a hit into texture space and marches it
/// (PAPER.md s.4-5). The reference renderer (render/renderer.h) and the baker
/// (bake/baker.h) both shade through it; neither needs the other.

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/fiber/fiber_shader.h"
#include "core/geometry/quad_patch.h"
#include "core/march/light_transmittance.h"
#include "core/march/volume_march.h"
#include "core/scene/scene.h"
#include "core/texture/volume_texture.h"
#include "core/util/random.h"

namespace clothbake {

/// What one cloth surface point shows along a ray: by default the march
/// (ClothScene::shade_surface); lookup-render substitutes a baked lookup
/// (bake/baker.h, lookup_shader).
using SurfaceShader = std::function<MarchResult(int object, int quad, float s, float t,
                                                const Imath::V3f& ray_dir_world, Rng& rng)>;

class ClothScene {
 public:
  /// Prepares every object: its volume texture (the object's `volume` if
  /// set, else generated from its cloth spec and refused over the memory
  /// budget), its fibre shader and its quad patches. `volumes`, if given,
  /// replaces the volume of each object (tests, bakes reusing one, a
  /// material bake lending its colour-free volume: colour_free_volume).
  ClothScene(const Scene& scene, uint64_t memory_budget_bytes,
             std::vector<std::shared_ptr<const VolumeTexture>> volumes = {});
  ~ClothScene();
  ClothScene(const ClothScene&) = delete;
  ClothScene& operator=(const ClothScene&) = delete;

  const Scene& scene() const { return m_scene; }
  int object_count() const;
  int quad_count(int object) const;
  const VolumeTexture& volume(int object) const;
  const QuadPatch& patch(int object, int quad) const;

  /// Builds the light caches (Cached transmittance) once, for every valid
  /// quad; a no-op in ShadowMarch mode or when built already.
  void prepare_light_caches();
  /// Seconds spent preparing: volumes, fibre tables, patches, light caches.
  double setup_seconds() const { return m_setup_seconds; }

  /// The march at patch parameters (s, t) of a quad, for a ray arriving in
  /// direction `ray_dir_world` (front or back side): radiance and see-through
  /// of that one layer. Draws exactly two random numbers from `rng`.
  MarchResult shade_surface(int object, int quad, float s, float t, const Imath::V3f& ray_dir_world,
                            Rng& rng) const;

  /// World distance a ray arriving from the front at (s, t) travels inside
  /// the volume below the surface before it leaves it (0 from behind): the
  /// next cloth layer can only start beyond it.
  float world_distance_below(int object, int quad, float s, float t,
                             const Imath::V3f& ray_dir_world) const;

 private:
  struct Object;
  const Scene& m_scene;
  std::vector<Object> m_objects;
  bool m_caches_ready = false;
  double m_setup_seconds = 0.0;
};

}  // namespace clothbake
