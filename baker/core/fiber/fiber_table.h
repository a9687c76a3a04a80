#pragma once
/// Tabulated form of the ellipsoid fibre model (fiber_model.h), for speed.
///
/// The ellipsoid's response depends only on three angles: theta_L and theta_E
/// (angles of L and E from the fibre axis) and phi_D (azimuth between L and E
/// around the axis). Symmetries: mirror through the (axis, E) plane makes it
/// even in phi_D, and the ellipsoid is symmetric under axis -> -axis, so
/// (theta_L, theta_E) -> (pi - theta_L, pi - theta_E). The table stores
/// theta_E in [0, pi/2], theta_L in [0, pi], phi_D in [0, pi] and interpolates
/// trilinearly.

#include <cstdint>
#include <vector>

#include "core/fiber/fiber_model.h"

namespace clothbake {

/// The angles the fibre response depends on, in radians.
struct FiberAngles {
  float theta_light = 0.0f;  ///< angle between L and the fibre axis, [0, pi]
  float theta_eye = 0.0f;    ///< angle between E and the fibre axis, [0, pi]
  float phi_d = 0.0f;        ///< azimuth between L and E around the axis, [0, pi]; 0 if undefined
};

/// Exact (libm) angles of L and E about the axis `tangent`, for reports and tests.
/// Inputs need not be unit; a zero or non-finite input gives all zeros.
FiberAngles fiber_angles(const Imath::V3f& tangent, const Imath::V3f& to_light,
                         const Imath::V3f& to_eye);

struct FiberTableParams {
  EllipsoidFiberParams fiber;  ///< the model being tabulated (aspect, exponent, samples per entry)
  int theta_bins = 48;         ///< entries over theta_L in [0, pi]; theta_E gets half + 1
  int phi_bins = 48;           ///< entries over phi_D in [0, pi]
  uint64_t seed = 1;           ///< jitter seed for the table's entries
};

class FiberTable {
 public:
  /// Builds the table (parallel, deterministic for any thread count).
  static FiberTable build(const FiberTableParams& params);

  /// Trilinear lookup. Same vector conventions as ellipsoid_fiber(), including a
  /// zero tangent (answered from a small sphere table over the phase angle).
  FiberResponse eval(const Imath::V3f& tangent, const Imath::V3f& to_light,
                     const Imath::V3f& to_eye) const;

  const FiberTableParams& params() const { return m_params; }
  size_t entry_count() const { return m_diffuse.size(); }
  /// The stored entries, laid out [theta_e][theta_l][phi_d] (for tests and caches).
  const std::vector<float>& diffuse_entries() const { return m_diffuse; }
  const std::vector<float>& specular_entries() const { return m_specular; }

 private:
  FiberTableParams m_params;
  int m_n_theta_l = 0, m_n_theta_e = 0, m_n_phi = 0;
  std::vector<float> m_diffuse, m_specular;                // [theta_e][theta_l][phi]
  std::vector<float> m_sphere_diffuse, m_sphere_specular;  // aspect 1, [phase], theta_L's grid
};

}  // namespace clothbake
