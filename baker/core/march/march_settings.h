#pragma once
/// The choices a march makes, as a renderer or baker sets them
/// (RenderSettings in core/scene/scene.h carries them): the march needs these
/// and nothing else of the scene.

namespace clothbake {

/// How light reaching a march sample is attenuated by the cloth.
enum class TransmittanceMode {
  ShadowMarch,  ///< the paper's step 3a: march from every sample toward every light
  Cached        ///< per quad and light, once over the cells, then looked up (PAPER.md s.5)
};

/// What a sample scatters.
enum class ShadingMode {
  Fiber,     ///< the fibre reflection model with the cell's coefficients (the paper)
  Isotropic  ///< albedo x isotropic phase 1/(4 pi): for analytic checks (testscenes/slab)
};

}  // namespace clothbake
