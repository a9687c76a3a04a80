// Tabulated ellipsoid fibre model (Kimoto & Ohno, PAPER.md s.3), for speed.
//
// Entry (i_e, i_l, i_p) holds ellipsoid_fiber() at theta_E = i_e * pi/2/(n_e-1),
// theta_L = i_l * pi/(n_l-1), phi_D = i_p * pi/(n_p-1), seeded with
// hash_key(seed, entry index), so every entry is a pure function of its index and
// the table is bit-identical for any thread count. Nodes that are one physical
// configuration share one evaluation (that of their canonical node), so MC noise
// cannot make the table disagree with the model's symmetries:
//  - theta_E = 0 or theta_L in {0, pi}: the azimuth is undefined, use phi_D = 0;
//  - theta_E = pi/2, the fold: (theta_L, E) ~ (pi - theta_L, E), use theta_L <= pi/2.
// A small extra table over the phase angle serves a zero tangent (the sphere),
// as ellipsoid_fiber() does.
//
// Lookups avoid libm's acos/atan2: polynomial forms (Abramowitz & Stegun 4.4.46
// and 4.4.49) are accurate to 2e-8 and 1e-5 rad, far below a bin (~0.065 rad).

#include "core/fiber/fiber_table.h"
#include "core/util/vector_math.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/util/error.h"
#include "core/util/random.h"

namespace clothbake {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// acos on [-1, 1], |error| <= 2e-8 rad (A&S 4.4.46), plus float rounding.
float fast_acos(float x) {
  x = std::clamp(x, -1.0f, 1.0f);
  const float ax = std::abs(x);
  float p = -0.0012624911f;
  p = p * ax + 0.0066700901f;
  p = p * ax - 0.0170881256f;
  p = p * ax + 0.0308918810f;
  p = p * ax - 0.0501743046f;
  p = p * ax + 0.0889789874f;
  p = p * ax - 0.2145988016f;
  p = p * ax + 1.5707963050f;
  const float r = std::sqrt(1.0f - ax) * p;
  return x >= 0.0f ? r : kPi - r;
}

/// atan2(y, x) for y >= 0, in [0, pi], |error| <= 1e-5 rad (A&S 4.4.49).
float fast_atan2_upper(float y, float x) {
  const float ax = std::abs(x);
  const float hi = std::max(ax, y), lo = std::min(ax, y);
  if (!(hi > 0.0f)) return 0.0f;  // both zero: azimuth undefined, any value will do
  const float z = lo / hi, z2 = z * z;
  float p = 0.0208351f;
  p = p * z2 - 0.0851330f;
  p = p * z2 + 0.1801410f;
  p = p * z2 - 0.3302995f;
  p = p * z2 + 0.9998660f;
  float r = p * z;
  if (y > ax) r = kPi / 2.0f - r;
  if (x < 0.0f) r = kPi - r;
  return r;
}

/// Splits a coordinate in [0, 1] * (n - 1) into a cell index and a fraction.
void grid_cell(float coordinate, int n, int& index, float& frac) {
  const float c = std::clamp(coordinate, 0.0f, static_cast<float>(n - 1));
  index = std::min(static_cast<int>(c), n - 2);
  frac = c - static_cast<float>(index);
}

/// The three angles from normalised vectors.
/// Uses the polynomial acos/atan2 when `fast`, libm otherwise.
FiberAngles angles_of(const Imath::V3f& axis, const Imath::V3f& light, const Imath::V3f& eye,
                      bool fast) {
  float cos_l = std::clamp(axis.dot(light), -1.0f, 1.0f);
  float cos_e = std::clamp(axis.dot(eye), -1.0f, 1.0f);
  // phi_D from L_perp x E_perp = ((L x E).v) v and L_perp.E_perp = L.E - cos_l cos_e;
  // both are ~0 when L or E lies along the axis, where the response has no azimuth.
  const float y = std::abs(axis.dot(light.cross(eye)));
  const float x = light.dot(eye) - cos_l * cos_e;
  FiberAngles a;
  if (fast) {
    a.theta_light = fast_acos(cos_l);
    a.theta_eye = fast_acos(cos_e);
    a.phi_d = fast_atan2_upper(y, x);
  } else {
    a.theta_light = std::acos(cos_l);
    a.theta_eye = std::acos(cos_e);
    a.phi_d = (x == 0.0f && y == 0.0f) ? 0.0f : std::atan2(y, x);
  }
  return a;
}

}  // namespace

FiberAngles fiber_angles(const Imath::V3f& tangent, const Imath::V3f& to_light,
                         const Imath::V3f& to_eye) {
  Imath::V3f axis = tangent, light = to_light, eye = to_eye;
  if (!finite(axis) || !finite(light) || !finite(eye) || !normalize_safe(axis) ||
      !normalize_safe(light) || !normalize_safe(eye))
    return {};
  return angles_of(axis, light, eye, /*fast=*/false);
}

FiberTable FiberTable::build(const FiberTableParams& params) {
  if (params.theta_bins < 2)
    throw InputError("fiber_table.theta_bins",
                     "need at least 2 entries, got " + std::to_string(params.theta_bins));
  if (params.phi_bins < 2)
    throw InputError("fiber_table.phi_bins",
                     "need at least 2 entries, got " + std::to_string(params.phi_bins));

  FiberTable table;
  table.m_params = params;
  table.m_n_theta_l = params.theta_bins;
  table.m_n_theta_e = params.theta_bins / 2 + 1;
  table.m_n_phi = params.phi_bins;
  const size_t n_main = size_t(table.m_n_theta_e) * table.m_n_theta_l * table.m_n_phi;
  const size_t n_sphere = size_t(table.m_n_theta_l);
  table.m_diffuse.resize(n_main);
  table.m_specular.resize(n_main);
  table.m_sphere_diffuse.resize(n_sphere);
  table.m_sphere_specular.resize(n_sphere);

  const double step_l = std::numbers::pi / (table.m_n_theta_l - 1);
  const double step_e = std::numbers::pi / 2.0 / (table.m_n_theta_e - 1);
  const double step_p = std::numbers::pi / (table.m_n_phi - 1);
  const Imath::V3f axis(0.0f, 0.0f, 1.0f);

  // Main table: the fibre along z, L in the xz plane, E at azimuth phi_D.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n_main, 64), [&](const auto& range) {
    for (size_t index = range.begin(); index != range.end(); ++index) {
      // Canonical node of this entry (see the file comment).
      const size_t n_l = table.m_n_theta_l, n_p = table.m_n_phi;
      size_t i_p = index % n_p;
      size_t i_l = (index / n_p) % n_l;
      const size_t i_e = index / (n_p * n_l);
      if (i_e + 1 == size_t(table.m_n_theta_e)) i_l = std::min(i_l, n_l - 1 - i_l);
      if (i_e == 0 || i_l == 0 || i_l + 1 == n_l) i_p = 0;
      const size_t canonical = (i_e * n_l + i_l) * n_p + i_p;

      const double th_l = double(i_l) * step_l, th_e = double(i_e) * step_e;
      const double ph = double(i_p) * step_p;
      const Imath::V3f light(float(std::sin(th_l)), 0.0f, float(std::cos(th_l)));
      const Imath::V3f eye(float(std::sin(th_e) * std::cos(ph)),
                           float(std::sin(th_e) * std::sin(ph)), float(std::cos(th_e)));
      const FiberResponse r =
          ellipsoid_fiber(axis, light, eye, params.fiber, hash_key(params.seed, canonical));
      table.m_diffuse[index] = r.diffuse;
      table.m_specular[index] = r.specular;
    }
  });

  // Sphere table over the phase angle, for a zero tangent; indices follow the main ones.
  EllipsoidFiberParams sphere = params.fiber;
  sphere.aspect = 1.0f;
  tbb::parallel_for(size_t(0), n_sphere, [&](size_t i) {
    const double phase = double(i) * step_l;
    const Imath::V3f light(float(std::sin(phase)), 0.0f, float(std::cos(phase)));
    const FiberResponse r =
        ellipsoid_fiber(Imath::V3f(0.0f), light, axis, sphere, hash_key(params.seed, n_main + i));
    table.m_sphere_diffuse[i] = r.diffuse;
    table.m_sphere_specular[i] = r.specular;
  });
  return table;
}

FiberResponse FiberTable::eval(const Imath::V3f& tangent, const Imath::V3f& to_light,
                               const Imath::V3f& to_eye) const {
  if (m_diffuse.empty()) return {};
  if (!finite(tangent) || !finite(to_light) || !finite(to_eye)) return {};
  Imath::V3f axis = tangent, light = to_light, eye = to_eye;
  if (!normalize_safe(light) || !normalize_safe(eye)) return {};

  const float scale_l = float(m_n_theta_l - 1) / kPi;
  if (!normalize_safe(axis)) {
    // Zero tangent: the sphere, a function of the phase angle only.
    int i;
    float f;
    grid_cell(fast_acos(light.dot(eye)) * scale_l, m_n_theta_l, i, f);
    return {m_sphere_diffuse[i] + f * (m_sphere_diffuse[i + 1] - m_sphere_diffuse[i]),
            m_sphere_specular[i] + f * (m_sphere_specular[i + 1] - m_sphere_specular[i])};
  }
  // The spheroid is symmetric under axis -> -axis: fold E into theta_E <= pi/2.
  if (axis.dot(eye) < 0.0f) axis = -axis;
  const FiberAngles a = angles_of(axis, light, eye, /*fast=*/true);

  // Trilinear interpolation over [theta_e][theta_l][phi].
  int ie, il, ip;
  float fe, fl, fp;
  grid_cell(a.theta_eye * (float(m_n_theta_e - 1) / (kPi / 2.0f)), m_n_theta_e, ie, fe);
  grid_cell(a.theta_light * scale_l, m_n_theta_l, il, fl);
  grid_cell(a.phi_d * (float(m_n_phi - 1) / kPi), m_n_phi, ip, fp);
  const size_t stride_l = size_t(m_n_phi), stride_e = size_t(m_n_phi) * m_n_theta_l;
  const size_t base = ie * stride_e + il * stride_l + ip;
  auto lerp3 = [&](const std::vector<float>& t) {
    const float* p = t.data() + base;
    auto lerp_phi = [&](size_t o) { return p[o] + fp * (p[o + 1] - p[o]); };
    const float e0 = lerp_phi(0) + fl * (lerp_phi(stride_l) - lerp_phi(0));
    const float e1 = lerp_phi(stride_e) + fl * (lerp_phi(stride_e + stride_l) - lerp_phi(stride_e));
    return e0 + fe * (e1 - e0);
  };
  return {lerp3(m_diffuse), lerp3(m_specular)};
}

}  // namespace clothbake
