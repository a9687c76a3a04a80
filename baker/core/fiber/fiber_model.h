#pragma once
/// Fibre reflection model: Kimoto & Ohno (c. 1990), section 3 (PAPER.md s.3).
///
/// A fibre is a prolate ellipsoid (spheroid) whose long axis follows the cell's
/// fibre tangent. Seen from direction E and lit from L, its brightness is the
/// Lambert term (diffuse) and the Phong term (specular) averaged over the part
/// of the ellipsoid visible from E. The points are found by jittered rays along
/// E over the ellipsoid's silhouette, so they are uniform in projected area.
///
/// All vectors passed here live in one common space (whatever space the caller
/// works in: fibre, texture or world); only their relative angles matter. All
/// are unit vectors pointing AWAY from the fibre: `to_light` toward the light,
/// `to_eye` toward the viewer.

#include <cstdint>

#include <Imath/ImathVec.h>

namespace clothbake {

/// Mean reflection of one fibre, for unit diffuse and unit specular coefficient.
struct FiberResponse {
  float diffuse = 0.0f;   ///< mean of max(0, n.L) over visible points, in [0, 1]
  float specular = 0.0f;  ///< mean of Phong max(0, R.E)^n over the same points, in [0, 1]
};

/// Which form of the fibre model to evaluate.
enum class FiberModelKind { Ellipsoid, Table, KajiyaKay };

/// Parameters of the ellipsoid model.
struct EllipsoidFiberParams {
  float aspect = 8.0f;     ///< long semi-axis / short semi-axis, >= 1 (1 = sphere)
  float exponent = 20.0f;  ///< Phong exponent n, > 0
  int samples = 64;        ///< jittered silhouette samples N (rounded up to a square)
};

/// Direct Monte Carlo evaluation of the ellipsoid model with N jittered samples.
/// `seed` picks the jitter pattern; equal inputs and seed give equal bits.
/// Never returns NaN/Inf, for any unit inputs (parallel, antiparallel, below any
/// horizon); a zero `tangent` is treated as a sphere. A non-finite input or a
/// zero L or E gives {0, 0}; aspect is clamped to [1, 1e4].
FiberResponse ellipsoid_fiber(const Imath::V3f& tangent, const Imath::V3f& to_light,
                              const Imath::V3f& to_eye, const EllipsoidFiberParams& params,
                              uint64_t seed);

/// Kajiya & Kay (1989) closed form for an infinitely thin cylinder:
///   diffuse  = (pi/4) sin(t, L)    (scaled so it equals the ellipsoid's cylinder
///                                   limit when E and L share an azimuth)
///   specular = max(0, sin(t,L) sin(t,E) - cos(t,L) cos(t,E))^n
/// A zero tangent (no axis, no highlight cone) gives the Lambert-sphere diffuse
/// (sphere_diffuse_exact) and zero specular.
FiberResponse kajiya_kay_fiber(const Imath::V3f& tangent, const Imath::V3f& to_light,
                               const Imath::V3f& to_eye, float exponent);

/// Exact sphere (aspect 1) limit: the Lambert-sphere phase law
/// 2/(3 pi) (sin a + (pi - a) cos a), a = angle between L and E.
double sphere_diffuse_exact(double phase_angle);

/// Exact cylinder limit (aspect -> infinity) of the diffuse mean:
/// sin(theta_L) (sin D + (pi - D) cos D) / 4, theta_L = angle(L, axis),
/// D = azimuth between L and E around the axis, in [0, pi].
double cylinder_diffuse_limit(double theta_light, double azimuth_difference);

}  // namespace clothbake
