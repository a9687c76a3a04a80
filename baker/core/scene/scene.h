#pragma once
/// Everything a render needs, filled by the I/O layer (docs/formats/scene.md).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/fiber/fiber_model.h"
#include "core/geometry/camera.h"
#include "core/geometry/quad_mesh.h"
#include "core/march/march_settings.h"
#include "core/scene/light.h"
#include "core/texture/volume_texture.h"
#include "core/weave/cloth_spec.h"

namespace clothbake {

struct RenderSettings {
  int spp = 4;              ///< samples per pixel (jittered, stratified)
  float step_cells = 0.5f;  ///< march step as a fraction of the smallest cell edge
  FiberModelKind fiber_model = FiberModelKind::Table;
  int fiber_samples = 64;  ///< ellipsoid samples (direct model and table entries)
  TransmittanceMode transmittance = TransmittanceMode::Cached;
  ShadingMode shading = ShadingMode::Fiber;
  float cutoff = 1e-3f;  ///< stop the view march when transmittance falls below this
  uint64_t seed = 1;
  /// View transmittance below which a sample's lights are evaluated only at
  /// random (Russian roulette, volume_march.h); 0 evaluates them always.
  /// Unbiased; 0.25 renders the paper scene 1.8 x faster for 1.5% more noise
  /// (docs/design/renderer.md).
  float light_roulette = 0.25f;
};

struct ClothObject {
  std::string name;
  QuadMesh mesh;
  ClothSpec cloth;  ///< generates the texture, unless `volume` is set; always gives the fibre model
  /// A texture read from a file by the I/O layer (a scene's "volume"); when
  /// set it replaces the texture generated from `cloth`.
  std::shared_ptr<const VolumeTexture> volume;
  float repeats_per_uv = 40.0f;   ///< weave repeats per unit of UV, in u and in v
  float thickness_world = 0.01f;  ///< depth of the volume below the surface, world units
  float extinction_per_mm =
      40.0f;  ///< sigma: extinction of fibre at rho = 1, per mm of texture path
  Imath::V3f isotropic_albedo{0.8f, 0.8f, 0.8f};  ///< used in ShadingMode::Isotropic only
};

struct Scene {
  PinholeCamera camera;
  std::vector<Light> lights;
  std::vector<ClothObject> objects;
  Imath::V3f background{0.0f, 0.0f, 0.0f};  ///< linear RGB seen where no cloth is (alpha 0)
  RenderSettings settings;
};

}  // namespace clothbake
