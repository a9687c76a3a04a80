#pragma once
/// Light reaching a point inside the volume texture (PAPER.md s.5 step 3a),
/// in both forms the renderer offers:
///  - shadow_transmittance(): the paper's own, a march from the point toward
///    the light through the cells (a DDA, exact for cells of constant rho);
///  - TransmittanceCache: the same quantity computed once per quad and light
///    over the whole grid (layer by layer, each cell's segment to the next
///    layer exact, the rest interpolated) and then looked up trilinearly.
/// Transmittance = exp(-sigma * sum(rho * segment length)), lengths in mm of
/// texture space, sigma = extinction per mm at rho = 1.

#include <cmath>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/texture/volume_texture.h"

namespace clothbake {

/// Optical depth beyond which light is taken as fully blocked: T < 1e-4, a
/// thousandth of the view march's default cutoff, far below sampling noise.
inline constexpr float k_opaque_optical_depth = 9.2f;

/// Transmittance from p_texture to the face of the volume facing the light,
/// along `to_light_texture` (unit, texture space). A light in the texture's
/// plane (to_light.z ~ 0) never leaves a periodic slab: the march is capped
/// at 64 repeats.
float shadow_transmittance(const VolumeTexture& volume, const Imath::V3f& p_texture,
                           const Imath::V3f& to_light_texture, float extinction_per_mm);

class TransmittanceCache {
 public:
  TransmittanceCache() = default;
  /// Transmittance at every cell centre toward a light in direction
  /// `to_light_texture` (unit, texture space), the same for the whole quad.
  static TransmittanceCache build(const VolumeTexture& volume, const Imath::V3f& to_light_texture,
                                  float extinction_per_mm);

  /// Transmittance at p: optical depth interpolated trilinearly between cell
  /// centres (periodic in x and y) and toward 0 at the face the light enters
  /// by; interpolating depth rather than transmittance keeps a homogeneous
  /// slab exact (depth is linear in z there, transmittance is not).
  float lookup(const Imath::V3f& p_texture) const { return transmittance(lookup_depth(p_texture)); }
  /// The interpolated optical depth itself.
  float lookup_depth(const Imath::V3f& p_texture) const;
  /// Optical depth at p along `to_light_texture` (the cache's direction or a
  /// nearby one): marched exactly (DDA) from p to the next layer-centre plane
  /// toward the light, then the cached depth there, interpolated in x and y
  /// only. Removes the interpolation error inside the sample's own layer,
  /// where the weave's sharp yarn edges make trilinear interpolation poor.
  float march_then_lookup(const VolumeTexture& volume, const Imath::V3f& p_texture,
                          const Imath::V3f& to_light_texture, float extinction_per_mm) const;
  /// Optical depth toward a nearby direction `to_light_texture` (same side of
  /// the cloth): the cached depth scaled by the ratio of path lengths through
  /// the layers, |cached.z| / |to_light.z|: exact in a horizontally uniform
  /// volume, first-order elsewhere. Corrects for the light direction varying
  /// over a curved quad. Returns a negative value when the direction is on
  /// the other side of the cloth (the caller marches instead).
  float depth_scale_for(const Imath::V3f& to_light_texture) const;
  static float transmittance(float depth) {
    return depth >= k_opaque_optical_depth ? 0.0f : std::exp(-depth);
  }
  bool empty() const { return m_tau.empty(); }
  /// The cached optical depth at the centre of cell (i, j, k) (no wrapping):
  /// for copying the field into another layout (material/light_fields.h).
  float depth_at(int i, int j, int k) const { return m_tau[(size_t(k) * m_ny + j) * m_nx + i]; }

 private:
  int m_nx = 0, m_ny = 0, m_nz = 0;
  Imath::V3f m_cell{1, 1, 1};
  bool m_from_above = true;
  Imath::V3f m_to_light{0, 0, 1};
  std::vector<float> m_tau;  // optical depth toward the light at cell centres, [k][j][i]
};

}  // namespace clothbake
