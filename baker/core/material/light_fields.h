#pragma once
/// Transmittance toward every light node of a material at once. The volume
/// under any surface point is the same flat periodic slab, so the light
/// reaching a point inside it toward one direction is one field over the
/// repeat, the same under every texel: each node's field is built once
/// (TransmittanceCache::build, exact per cell layer) on a grid `supersample`
/// times finer than the cells, and a view march reads all nodes' fields with
/// one set of trilinear weights per sample (the nodes are interleaved).
///
/// Optical depth is interpolated, not transmittance (exact for a homogeneous
/// slab); between the outermost layer's centres and the face the light
/// enters by it falls linearly to 0, and beyond the other outermost layer it
/// is held, as TransmittanceCache::lookup_depth does.

#include <cstddef>
#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/texture/volume_texture.h"

namespace clothbake {

class LightFieldSet {
 public:
  LightFieldSet() = default;
  /// One field per direction of `to_light_texture` (unit, texture space).
  /// Deterministic; parallel inside each field's build.
  static LightFieldSet build(const VolumeTexture& volume,
                             std::span<const Imath::V3f> to_light_texture, float extinction_per_mm,
                             int supersample);

  /// The fields of a window of `volume`'s cells only: `cells_x` x `cells_y`
  /// columns from cell (x0, y0) on (indices wrap), built as if the window
  /// were the repeat (a ray that leaves it comes back in at the other side).
  /// A material addressed per crossing builds one per block around its
  /// crossing; a point is read in the window's copy nearest the window's
  /// centre, so that the march may run in the whole repeat's coordinates.
  /// A window as wide as the volume is the whole field exactly.
  static LightFieldSet build_window(const VolumeTexture& volume, int x0, int y0, int cells_x,
                                    int cells_y, std::span<const Imath::V3f> to_light_texture,
                                    float extinction_per_mm, int supersample);
  static size_t bytes_for_window(const VolumeTexture& volume, int cells_x, int cells_y, int lights,
                                 int supersample);

  int light_count() const { return m_lights; }
  /// Optical depth toward every light at p_texture: depth[l], l < light_count().
  void depths(const Imath::V3f& p_texture, float* depth) const;
  /// Transmittance toward every light: exp(-depth), 0 past the opaque depth.
  void transmittances(const Imath::V3f& p_texture, float* transmittance) const;
  size_t bytes() const { return m_tau.size() * sizeof(float); }
  /// Bytes the set would take for this volume, light count and supersample.
  static size_t bytes_for(const VolumeTexture& volume, int lights, int supersample);

 private:
  int m_nx = 0, m_ny = 0, m_nz = 0;  // field points in x, y; z: nz layer centres + 2 faces
  int m_lights = 0;
  Imath::V3f m_spacing{1, 1, 1};  // between field points, mm
  float m_thickness = 0.0f;
  // A window's: its corner and extent in the volume's texture mm, and the
  // volume's repeat (0: the field is the whole repeat's).
  Imath::V2f m_origin{0.0f, 0.0f}, m_window{0.0f, 0.0f}, m_repeat{0.0f, 0.0f};
  std::vector<float> m_tau;  // [((kz * ny + j) * nx + i) * lights + l], kz = 0: bottom face
};

}  // namespace clothbake
