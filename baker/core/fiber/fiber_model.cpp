// Fibre reflection model: Kimoto & Ohno (c. 1990), section 3 (PAPER.md s.3).
//
// The ellipsoid is evaluated in the orthonormal "view" frame (u, w, E): E points
// to the eye, u is the fibre axis projected on the plane perpendicular to E and
// w = E x u. In that frame the axis is v = (sin t, 0, cos t), the silhouette is
// the ellipse with semi-axes h_u = sqrt(cos^2 t + aspect^2 sin^2 t) along u and
// 1 along w, and the ray through the silhouette point q = (X, Y, 0) has a closed
// form hit: with x(tau) = q + tau E and the fibre's axial coordinate scaled by
// 1/aspect (so the spheroid becomes the unit sphere), the quadratic
//   A tau^2 + 2 B tau + C = 0,  A = sin^2 t + cos^2 t / aspect^2,
//   B = X sin t cos t (1/aspect^2 - 1)
// has discriminant B^2 - A C = A (1 - r^2), r = the sample's radius in the unit
// disk before it is scaled to the ellipse. So no sample can miss: a rounding
// overshoot (r^2 > 1) is clamped onto the silhouette (discriminant 0).

#include "core/fiber/fiber_model.h"
#include "core/util/vector_math.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/util/random.h"

namespace clothbake {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// Largest aspect evaluated. The ends' effect falls as 1/aspect^2 (< 1e-8 here)
/// while float rounding of the hit point grows as eps * aspect (~2e-5 here).
constexpr float kMaxAspect = 1.0e4f;

/// Any unit vector perpendicular to unit `n` (Duff et al. 2017 branchless basis).
Imath::V3f any_perpendicular(const Imath::V3f& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return Imath::V3f(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
}

/// The axis as a line: flips `v` so its largest-magnitude component is positive.
/// v and -v describe the same spheroid; this makes them give identical bits.
Imath::V3f canonical_axis(const Imath::V3f& v) {
  const float ax = std::abs(v.x), ay = std::abs(v.y), az = std::abs(v.z);
  const float c = (ax >= ay && ax >= az) ? v.x : (ay >= az ? v.y : v.z);
  return c < 0.0f ? -v : v;
}

/// sin and cos on [-pi/4, pi/4] by Taylor polynomials (|error| < 4e-7), a
/// fraction of libm's cost; they only place samples, and r^2 stays exact.
void sincos_quarter(float x, float& s, float& c) {
  const float x2 = x * x;
  s = x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040))));
  c = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320))));
}

/// Shirley & Chiu (1997) concentric map from [0,1)^2 to the unit disk, area
/// preserving. Also returns the disk radius squared, exactly r * r.
void concentric_disk(float sx, float sy, float& dx, float& dy, float& r2) {
  const float a = 2.0f * sx - 1.0f;
  const float b = 2.0f * sy - 1.0f;
  if (a == 0.0f && b == 0.0f) {
    dx = dy = r2 = 0.0f;
    return;
  }
  float s, c;
  if (std::abs(a) > std::abs(b)) {
    sincos_quarter((kPi / 4.0f) * (b / a), s, c);  // phi = pi/4 (b/a)
    dx = a * c;
    dy = a * s;
    r2 = a * a;
  } else {
    sincos_quarter((kPi / 4.0f) * (a / b), s, c);  // phi = pi/2 - pi/4 (a/b)
    dx = b * s;
    dy = b * c;
    r2 = b * b;
  }
}

}  // namespace

// About 85 lines, kept whole: the fibre reflection model of PAPER.md s.3 in
// the paper's order (frame, visible part of the ellipsoid, jittered Lambert
// + Phong over it), so it can be read against the paper line by line.
FiberResponse ellipsoid_fiber(const Imath::V3f& tangent, const Imath::V3f& to_light,
                              const Imath::V3f& to_eye, const EllipsoidFiberParams& params,
                              uint64_t seed) {
  // Inputs: normalise defensively; NaN/Inf or a zero L/E has no answer.
  if (!finite(tangent) || !finite(to_light) || !finite(to_eye)) return {};
  Imath::V3f light = to_light, eye = to_eye, axis = tangent;
  if (!normalize_safe(light) || !normalize_safe(eye)) return {};
  float aspect = std::isfinite(params.aspect) ? params.aspect : kMaxAspect;
  aspect = std::clamp(aspect, 1.0f, kMaxAspect);
  if (!normalize_safe(axis)) {
    aspect = 1.0f;  // zero tangent: no axis, a sphere
    axis = any_perpendicular(eye);
  }
  axis = canonical_axis(axis);
  const float exponent = params.exponent >= 0.0f ? params.exponent : 0.0f;  // also NaN -> 0

  // View frame (u, w, E); the axis is v = sin_t u + cos_t E with sin_t >= 0.
  const float cos_t = std::clamp(axis.dot(eye), -1.0f, 1.0f);
  Imath::V3f u = axis - cos_t * eye;
  const float u_len = u.length();
  float sin_t;
  if (u_len > 1.0e-6f) {
    u /= u_len;
    sin_t = u_len;
  } else {
    u = any_perpendicular(eye);  // axis along E: any u, the silhouette is a circle
    sin_t = 0.0f;
  }
  const Imath::V3f w = eye.cross(u);
  const float l_u = light.dot(u), l_w = light.dot(w), l_e = light.dot(eye);

  // Silhouette and intersection constants (see the file comment).
  const float inv_a2 = 1.0f / (aspect * aspect);
  const float h_u = std::sqrt(cos_t * cos_t + aspect * aspect * sin_t * sin_t);
  const float quad_a = sin_t * sin_t + cos_t * cos_t * inv_a2;
  const float sqrt_a = std::sqrt(quad_a);
  const float b_per_x = sin_t * cos_t * (inv_a2 - 1.0f);

  // Stratified jittered samples over the silhouette.
  const int64_t requested = std::max(params.samples, 1);
  int64_t k = static_cast<int64_t>(std::ceil(std::sqrt(static_cast<double>(requested))));
  while (k * k < requested) ++k;
  const float inv_k = 1.0f / static_cast<float>(k);
  Rng rng(hash_key(seed));  // hashed: Rng(s + 1) would replay Rng(s)'s stream shifted by one
  double sum_diffuse = 0.0, sum_specular = 0.0;
  for (int64_t j = 0; j < k; ++j) {
    for (int64_t i = 0; i < k; ++i) {
      const float jx = rng.next_float(), jy = rng.next_float();
      float s, t, r2;
      concentric_disk((static_cast<float>(i) + jx) * inv_k, (static_cast<float>(j) + jy) * inv_k, s,
                      t, r2);
      const float x = s * h_u, y = t;

      // Nearest hit along E: the larger root, in the cancellation-free form.
      const float b = x * b_per_x;
      const float sqrt_disc = sqrt_a * std::sqrt(std::max(0.0f, 1.0f - r2));
      float tau;
      if (b <= 0.0f) {
        tau = (sqrt_disc - b) / quad_a;
      } else {
        const float c = x * x * (cos_t * cos_t + sin_t * sin_t * inv_a2) + y * y - 1.0f;
        const float q = -(b + sqrt_disc);
        tau = q < 0.0f ? c / q : 0.0f;
      }

      // Normal: gradient (x_perp, x_axial / aspect^2) = p + (1/a^2 - 1) x_axial v.
      const float axial = x * sin_t + tau * cos_t;
      const float g_u = x + (inv_a2 - 1.0f) * axial * sin_t;
      const float g_e = tau + (inv_a2 - 1.0f) * axial * cos_t;
      const float g_len2 = g_u * g_u + y * y + g_e * g_e;
      if (!(g_len2 > 0.0f)) continue;  // unreachable for a unit sphere in scaled space
      const float inv_len = 1.0f / std::sqrt(g_len2);
      const float n_dot_l = std::min(1.0f, (g_u * l_u + y * l_w + g_e * l_e) * inv_len);
      if (n_dot_l <= 0.0f) continue;
      sum_diffuse += n_dot_l;

      // Phong: R.E = 2 (n.L)(n.E) - L.E.
      const float n_dot_e = g_e * inv_len;
      const float r_dot_e = std::min(1.0f, 2.0f * n_dot_l * n_dot_e - l_e);
      if (r_dot_e > 0.0f) sum_specular += std::pow(r_dot_e, exponent);
    }
  }
  const double n = static_cast<double>(k * k);
  FiberResponse out;
  out.diffuse = static_cast<float>(std::clamp(sum_diffuse / n, 0.0, 1.0));
  out.specular = static_cast<float>(std::clamp(sum_specular / n, 0.0, 1.0));
  return out;
}

FiberResponse kajiya_kay_fiber(const Imath::V3f& tangent, const Imath::V3f& to_light,
                               const Imath::V3f& to_eye, float exponent) {
  if (!finite(tangent) || !finite(to_light) || !finite(to_eye)) return {};
  Imath::V3f light = to_light, eye = to_eye, axis = tangent;
  if (!normalize_safe(light) || !normalize_safe(eye)) return {};
  if (!normalize_safe(axis)) {
    // No axis, no highlight cone: the Lambert sphere (the ellipsoid's aspect-1 limit).
    const double phase = std::acos(std::clamp(static_cast<double>(light.dot(eye)), -1.0, 1.0));
    return {static_cast<float>(sphere_diffuse_exact(phase)), 0.0f};
  }
  const float cos_l = std::clamp(axis.dot(light), -1.0f, 1.0f);
  const float cos_e = std::clamp(axis.dot(eye), -1.0f, 1.0f);
  const float sin_l = std::sqrt(1.0f - cos_l * cos_l);
  const float sin_e = std::sqrt(1.0f - cos_e * cos_e);
  const float n = exponent >= 0.0f ? exponent : 0.0f;
  const float cone = std::min(1.0f, sin_l * sin_e - cos_l * cos_e);
  FiberResponse out;
  out.diffuse = std::min(1.0f, (kPi / 4.0f) * sin_l);
  out.specular = cone > 0.0f ? std::pow(cone, n) : 0.0f;
  return out;
}

double sphere_diffuse_exact(double phase_angle) {
  const double a = std::clamp(phase_angle, 0.0, std::numbers::pi);
  return 2.0 / (3.0 * std::numbers::pi) * (std::sin(a) + (std::numbers::pi - a) * std::cos(a));
}

double cylinder_diffuse_limit(double theta_light, double azimuth_difference) {
  const double d = std::clamp(azimuth_difference, 0.0, std::numbers::pi);
  return std::sin(theta_light) * (std::sin(d) + (std::numbers::pi - d) * std::cos(d)) / 4.0;
}

}  // namespace clothbake
