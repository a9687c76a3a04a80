#pragma once
/// The map m of Kimoto & Ohno section 4 (PAPER.md s.4) for one quad: the
/// bilinear patch through its four corners, mapped onto the volume texture's
/// top face through the mesh's UVs, with the local frame that carries
/// directions into texture space. Correct for non-planar quads: every
/// quantity is evaluated at the hit's own patch parameters (s, t).
/// The spaces are named in core/geometry/surface_frame.h.

#include <Imath/ImathVec.h>

#include "core/geometry/camera.h"
#include "core/geometry/quad_mesh.h"
#include "core/geometry/surface_frame.h"

namespace clothbake {

/// Where a ray meets a patch.
struct PatchHit {
  float t_world = 0.0f;      ///< ray parameter (world units along the unit direction)
  float s = 0.0f, t = 0.0f;  ///< patch parameters in [0, 1]^2
  bool front_facing = true;  ///< the ray arrives from the side N points to
};

class QuadPatch {
 public:
  QuadPatch() = default;
  /// Quad `quad_index` of `mesh`; `repeats_per_uv` weave repeats per UV unit;
  /// `repeat_mm` is the texture's repeat size (x, y) and `thickness_mm` its
  /// depth, which spans `thickness_world` in the scene. Degenerate quads (zero
  /// area, or UVs of zero area) make valid() false. Precisely, valid() needs:
  /// indices in range; four distinct, finite corners; positive, finite scales;
  /// a normal dP/ds x dP/dt that neither vanishes nor flips anywhere on
  /// [0,1]^2 (every corner normal has a component along the centre normal of
  /// more than 1e-6 x size^2; this rejects collinear, folded and bow-tie
  /// quads); and a UV Jacobian determinant of one sign, above 1e-6 x UV size^2,
  /// everywhere (mirrored UVs are fine).
  QuadPatch(const QuadMesh& mesh, int quad_index, float repeats_per_uv, Imath::V2f repeat_mm,
            float thickness_mm, float thickness_world);

  bool valid() const { return m_valid; }

  /// Nearest intersection with t_world in (t_min, t_max). Handles non-planar
  /// (twisted) quads exactly (Reshetov's ruling construction, Ray Tracing
  /// Gems ch. 8, in double precision). Edges count as inside, with a 1e-7
  /// parameter tolerance (then clamped), so a ray through a shared edge hits
  /// both neighbours. Rays parallel to a planar quad, and invalid patches, miss.
  /// t_world is in units of |direction| (world units for a unit direction).
  bool intersect(const Ray& ray_world, float t_min, float t_max, PatchHit& hit) const;

  Imath::V3f position_world(float s, float t) const;
  Imath::V2f uv(float s, float t) const;
  /// The point of the texture's top face that (s, t) maps to: x, y in mm
  /// (not wrapped into the repeat, so neighbouring quads agree), z = thickness_mm.
  Imath::V3f texture_point(float s, float t) const;
  /// The local frame at (s, t). Requires valid().
  SurfaceFrame frame(float s, float t) const;
  /// Inverse of position_world for a point on the patch: its (s, t), by Newton
  /// iteration from the centre. False if it does not converge inside [0,1]^2.
  /// Gauss-Newton on |P(s, t) - p|^2, so a point off the surface gets the
  /// parameters of its nearest patch point (a local minimum).
  bool parameters_of(const Imath::V3f& p_world, float& s, float& t) const;

  /// World-space bounding box of the patch (the convex hull of its corners).
  Imath::V3f bounds_min_world() const { return m_min; }
  Imath::V3f bounds_max_world() const { return m_max; }
  const Imath::V3f& corner_world(int i) const { return m_p[i]; }

 private:
  Imath::V3f m_p[4];   // corners, world
  Imath::V2f m_uv[4];  // corner UVs
  Imath::V3f m_min, m_max;
  float m_repeats_per_uv = 1.0f;
  Imath::V2f m_repeat_mm{1.0f, 1.0f};
  float m_thickness_mm = 1.0f, m_thickness_world = 1.0f;
  bool m_valid = false;
};

}  // namespace clothbake
