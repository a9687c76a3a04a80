#pragma once
/// Transmittance toward every light node of a material at once. The volume
/// under any surface point is the same flat periodic slab, so the light
/// reaching a point inside it toward one direction is one field over the
/// repeat, the same under every texel: each node's field is built once
/// (TransmittanceCache::build, exact per cell layer) on a grid `supersample`
/// times finer than the cells, and a view march reads all nodes' fields with
/// one set of trilinear weights per sample (the nodes are interleaved).
///
/// Two ways to read a field (LightFieldMethod):
///  - Interpolated: optical depth at the cells' centres, trilinear between
///    them (depth, not transmittance: exact for a homogeneous slab); between
///    the outermost layer's centres and the face the light enters by it falls
///    linearly to 0, beyond the other outermost layer it is held, as
///    TransmittanceCache::lookup_depth does. Right while a cell is not
///    opaque: on the paper's cloth a field cell holds an optical depth of
///    0.45. Where one holds several (a thick yarn at 8 cells a thread), the
///    depth jumps across a yarn's edge within one cell and the interpolation
///    puts shadow where the light still comes in: a 2.12 mm plain weave
///    rendered 7 % darker (docs/design/material.md, "Opaque cells").
///  - LayerMarch: optical depth at the face planes between layers; a sample
///    marches its own layer toward each light cell by cell (the cells'
///    densities are held) to the face, and reads the face's depth where the
///    light's ray crosses it, bilinear in transmittance (the face's shadow
///    edges are as sharp as the cells': depth interpolated across them
///    darkened the mean). Exact inside the sample's layer, where the
///    interpolation's error was; about 6 x the march's time.

#include <cstddef>
#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/material/material_settings.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

class LightFieldSet {
 public:
  LightFieldSet() = default;
  /// One field per direction of `to_light_texture` (unit, texture space).
  /// Deterministic; parallel inside each field's build.
  static LightFieldSet build(const VolumeTexture& volume,
                             std::span<const Imath::V3f> to_light_texture, float extinction_per_mm,
                             int supersample,
                             LightFieldMethod method = LightFieldMethod::Interpolated);
  /// Auto resolved for this volume (Interpolated and LayerMarch returned as
  /// given): LayerMarch when sigma x the densest cell's rho x the longest
  /// field-cell edge exceeds k_layer_march_cell_depth.
  static LightFieldMethod resolve(LightFieldMethod method, const VolumeTexture& volume,
                                  float extinction_per_mm, int supersample);

  /// The fields of a window of `volume`'s cells only: `cells_x` x `cells_y`
  /// columns from cell (x0, y0) on (indices wrap), built as if the window
  /// were the repeat (a ray that leaves it comes back in at the other side).
  /// A material addressed per crossing builds one per block around its
  /// crossing; a point is read in the window's copy nearest the window's
  /// centre, so that the march may run in the whole repeat's coordinates.
  /// A window as wide as the volume is the whole field exactly.
  static LightFieldSet build_window(const VolumeTexture& volume, int x0, int y0, int cells_x,
                                    int cells_y, std::span<const Imath::V3f> to_light_texture,
                                    float extinction_per_mm, int supersample,
                                    LightFieldMethod method = LightFieldMethod::Interpolated);
  static size_t bytes_for_window(const VolumeTexture& volume, int cells_x, int cells_y, int lights,
                                 int supersample,
                                 LightFieldMethod method = LightFieldMethod::Interpolated);

  int light_count() const { return m_lights; }
  /// Optical depth toward every light at p_texture: depth[l], l < light_count().
  void depths(const Imath::V3f& p_texture, float* depth) const;
  /// Transmittance toward every light: exp(-depth), 0 past the opaque depth.
  void transmittances(const Imath::V3f& p_texture, float* transmittance) const;
  size_t bytes() const { return (m_tau.size() + m_rho.size()) * sizeof(float); }
  /// Bytes the set would take for this volume, light count and supersample.
  static size_t bytes_for(const VolumeTexture& volume, int lights, int supersample,
                          LightFieldMethod method = LightFieldMethod::Interpolated);

 private:
  /// An empty set with `fine`'s grid, spacing and thickness and `lights`
  /// nodes: what build and build_faces start from.
  static LightFieldSet shaped_like(const VolumeTexture& fine, size_t lights);
  static LightFieldSet build_faces(const VolumeTexture& fine,
                                   std::span<const Imath::V3f> to_light_texture,
                                   float extinction_per_mm);
  Imath::V3f in_window(const Imath::V3f& p_volume) const;
  void depths_interpolated(const Imath::V3f& p, float* depth) const;
  void depths_layer_march(const Imath::V3f& p, float* depth) const;

  LightFieldMethod m_method = LightFieldMethod::Interpolated;
  int m_nx = 0, m_ny = 0, m_nz = 0;  // field points in x, y; z: nz layer centres + 2 faces
  int m_lights = 0;
  Imath::V3f m_spacing{1, 1, 1};  // between field points, mm
  float m_thickness = 0.0f;
  // A window's: its corner and extent in the volume's texture mm, and the
  // volume's repeat (0: the field is the whole repeat's).
  Imath::V2f m_origin{0.0f, 0.0f}, m_window{0.0f, 0.0f}, m_repeat{0.0f, 0.0f};
  // Interpolated: [((kz * ny + j) * nx + i) * lights + l], kz = 0: bottom
  // face, 1..nz the layers' centres, nz + 1 the top face. LayerMarch: the
  // face planes z = kz dz, kz = 0 (bottom) .. nz (top), at the columns'
  // centres.
  std::vector<float> m_tau;
  // LayerMarch only: each cell's density, [(k * ny + j) * nx + i]; sigma;
  // each light's direction.
  std::vector<float> m_rho;
  float m_sigma = 0.0f;
  struct LightStep {
    bool from_above = true;
    float path_per_height = 1.0f;  // 1 / |to_light.z|
    float dir_x = 0.0f, dir_y = 0.0f;
    float inv_abs_x = 1.0f, inv_abs_y = 1.0f;
  };
  std::vector<LightStep> m_light;
};

}  // namespace clothbake
