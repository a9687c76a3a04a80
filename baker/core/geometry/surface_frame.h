#pragma once
/// The frame at a cloth surface point, and the conversions between the three
/// spaces clothbake works in. Every other file converts through these, so the
/// names of vectors (`*_world`, `*_local`, `*_texture`) say which one they
/// are in:
///   *world*: the scene;
///   *local*: the orthonormal frame T, B, N at a point, world units (the
///     space of the lookups' direction nodes, docs/formats/lookup.md);
///   *texture*: millimetres of the volume texture: x along the weft, y along
///     the warp, z up; the top face is z = size_mm.z.

#include <Imath/ImathVec.h>

namespace clothbake {

/// Orthonormal frame at a surface point plus the scale of the map m there.
/// With dP/dx, dP/dy the world tangents per texture mm (the Jacobian of the
/// patch times the inverse of the UV map's, texture x and y in mm):
/// T = dP/dx projected into the tangent plane, mm_per_world = (1 / (dP/dx . T),
/// 1 / (dP/dy . B), thickness_mm / thickness_world). Exact for rectangles with
/// axis-aligned UVs; where the UV map shears, the orthonormal frame drops the
/// shear (texture_from_world(dP/dx) is still (1, 0, 0), that of dP/dy is not
/// exactly (0, 1, 0)).
struct SurfaceFrame {
  Imath::V3f tangent_world;  ///< T: unit, direction in which texture x grows (in the tangent plane)
  Imath::V3f bitangent_world;  ///< B = N x T
  Imath::V3f normal_world;     ///< N: unit front normal, (dP/ds x dP/dt) direction
  /// Texture millimetres per world unit along T, B and N. The B entry is
  /// negative where the UVs are mirrored (texture y grows along -B).
  Imath::V3f mm_per_world;

  /// A world direction in the local frame: (d.T, d.B, d.N). The one place
  /// that projects onto the frame; the lookups' direction nodes live here.
  Imath::V3f local_from_world(const Imath::V3f& d_world) const {
    return {d_world.dot(tangent_world), d_world.dot(bitangent_world), d_world.dot(normal_world)};
  }
  /// A local direction (T, B, N components) as a world direction.
  Imath::V3f world_from_local(const Imath::V3f& d_local) const {
    return tangent_world * d_local.x + bitangent_world * d_local.y + normal_world * d_local.z;
  }
  /// A world direction (or offset) carried into texture space (mm).
  Imath::V3f texture_from_world(const Imath::V3f& d_world) const {
    return {d_world.dot(tangent_world) * mm_per_world.x,
            d_world.dot(bitangent_world) * mm_per_world.y,
            d_world.dot(normal_world) * mm_per_world.z};
  }
  /// A texture-space direction as a world direction (not normalised).
  Imath::V3f world_from_texture(const Imath::V3f& d_texture) const {
    return tangent_world * (d_texture.x / mm_per_world.x) +
           bitangent_world * (d_texture.y / mm_per_world.y) +
           normal_world * (d_texture.z / mm_per_world.z);
  }
};

}  // namespace clothbake
