// The map m of Kimoto & Ohno section 4 (PAPER.md s.4): a quad as a bilinear
// patch, its exact ray intersection, its inverse and its local frame.
//
// Ray/patch intersection follows the geometric construction of A. Reshetov,
// "Cool Patches: A Geometric Approach to Ray/Bilinear Patch Intersections",
// Ray Tracing Gems (2019), ch. 8: the patch is swept by straight rulings; the
// ray meets the ruling at parameter u only if ray and ruling are coplanar,
// which is a quadratic in u; the position along the ruling and the ray
// distance then follow from a line/line solve. Everything runs in double
// precision on corners taken relative to the ray origin.

#include "core/geometry/quad_patch.h"

#include <algorithm>
#include <cmath>

namespace clothbake {
namespace {

using Imath::V2d;
using Imath::V3d;
using Imath::V3f;

/// Parameters within this distance outside [0, 1] still count as a hit (then
/// clamped), so rays through a shared edge hit both neighbours.
constexpr double kEdgeEps = 1e-7;
/// Relative size below which an area (a cross product) counts as zero.
constexpr double kRelArea = 1e-6;

V3d to_d(const V3f& v) { return V3d(v.x, v.y, v.z); }
V3f to_f(const V3d& v) { return V3f(float(v.x), float(v.y), float(v.z)); }
double cross2(const V2d& a, const V2d& b) { return a.x * b.y - a.y * b.x; }

template <typename V>
V bilerp(const V (&c)[4], double s, double t) {
  return c[0] * ((1 - s) * (1 - t)) + c[1] * (s * (1 - t)) + c[2] * (s * t) + c[3] * ((1 - s) * t);
}
/// dP/ds and dP/dt of the bilinear interpolation of c.
template <typename V>
void bilerp_derivatives(const V (&c)[4], double s, double t, V& d_ds, V& d_dt) {
  d_ds = (c[1] - c[0]) * (1 - t) + (c[2] - c[3]) * t;
  d_dt = (c[3] - c[0]) * (1 - s) + (c[2] - c[1]) * s;
}

/// True if the normal dP/ds x dP/dt never vanishes or flips on [0,1]^2. That
/// cross product is the bilinear interpolation of its four corner values, so it
/// is enough that every corner value has a component along the centre value
/// (their mean) above `eps` times the squared patch size.
bool normal_nonvanishing(const V3d (&corner)[4], double size, double eps) {
  const V3d centre = (corner[0] + corner[1] + corner[2] + corner[3]) * 0.25;
  const double centre_len = centre.length();
  const double min_area = eps * size * size;
  if (!(centre_len > min_area)) return false;
  for (const V3d& c : corner)
    if (!(c.dot(centre) / centre_len > min_area)) return false;
  return true;
}

/// Roots in [-kEdgeEps, 1 + kEdgeEps] of a + b u + c u^2 = 0, computed without
/// cancellation (the small root is a / q, never (-b + sqrt) / 2c), so a planar
/// quad, where c vanishes, loses no precision. Returns the number of roots.
int unit_roots(double a, double b, double c, double (&u)[2]) {
  const double disc = b * b - 4.0 * a * c;
  if (!(disc >= 0.0)) return 0;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double cand[2];
  int n = 0;
  if (q != 0.0) {
    cand[n++] = a / q;
    if (c != 0.0) cand[n++] = q / c;
  } else if (c != 0.0) {
    cand[n++] = 0.0;  // b = 0 and disc = 0 force a = 0: a double root at 0
  }
  int kept = 0;
  for (int i = 0; i < n; ++i)
    if (cand[i] >= -kEdgeEps && cand[i] <= 1.0 + kEdgeEps) u[kept++] = cand[i];
  return kept;
}

}  // namespace

QuadPatch::QuadPatch(const QuadMesh& mesh, int quad_index, float repeats_per_uv,
                     Imath::V2f repeat_mm, float thickness_mm, float thickness_world)
    : m_repeats_per_uv(repeats_per_uv),
      m_repeat_mm(repeat_mm),
      m_thickness_mm(thickness_mm),
      m_thickness_world(thickness_world) {
  // Indices: an out-of-range quad or corner leaves the patch invalid.
  if (quad_index < 0 || quad_index >= int(mesh.quads.size())) return;
  const QuadMesh::Quad& quad = mesh.quads[size_t(quad_index)];
  for (int i = 0; i < 4; ++i) {
    const int ip = quad.position[size_t(i)], iu = quad.uv[size_t(i)];
    if (ip < 0 || ip >= int(mesh.positions_world.size()) || iu < 0 || iu >= int(mesh.uvs.size()))
      return;
    m_p[i] = mesh.positions_world[size_t(ip)];
    m_uv[i] = mesh.uvs[size_t(iu)];
  }
  m_min = m_max = m_p[0];
  for (int i = 1; i < 4; ++i) {
    m_min =
        V3f(std::min(m_min.x, m_p[i].x), std::min(m_min.y, m_p[i].y), std::min(m_min.z, m_p[i].z));
    m_max =
        V3f(std::max(m_max.x, m_p[i].x), std::max(m_max.y, m_p[i].y), std::max(m_max.z, m_p[i].z));
  }

  // Map scales must be positive and finite.
  const auto positive = [](float v) { return std::isfinite(v) && v > 0.0f; };
  if (!positive(repeats_per_uv) || !positive(repeat_mm.x) || !positive(repeat_mm.y) ||
      !positive(thickness_mm) || !positive(thickness_world))
    return;

  // Corners: finite and pairwise distinct.
  V3d p[4];
  V2d uv[4];
  double size = 0.0, uv_size = 0.0;
  for (int i = 0; i < 4; ++i) {
    p[i] = to_d(m_p[i]);
    uv[i] = V2d(m_uv[i].x, m_uv[i].y);
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z) ||
        !std::isfinite(uv[i].x) || !std::isfinite(uv[i].y))
      return;
  }
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      if (m_p[i] == m_p[j]) return;
      size = std::max(size, (p[i] - p[j]).length());
      uv_size = std::max(uv_size, (uv[i] - uv[j]).length());
    }

  // Area: the normal dP/ds x dP/dt must not vanish or fold anywhere on the
  // patch, and neither may the UV Jacobian (so frame() can always invert it).
  V3d n[4];
  double uv_det[4];
  const double corner_s[4] = {0, 1, 1, 0}, corner_t[4] = {0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    V3d ps, pt;
    V2d us, ut;
    bilerp_derivatives(p, corner_s[i], corner_t[i], ps, pt);
    bilerp_derivatives(uv, corner_s[i], corner_t[i], us, ut);
    n[i] = ps.cross(pt);
    uv_det[i] = cross2(us, ut);
  }
  // Mirrored UVs have a negative determinant everywhere: test its sign-normalised form.
  if (uv_det[0] + uv_det[1] + uv_det[2] + uv_det[3] < 0.0)
    for (double& d : uv_det) d = -d;
  if (!normal_nonvanishing(n, size, kRelArea)) return;
  for (double d : uv_det)
    if (!(d > kRelArea * uv_size * uv_size)) return;
  m_valid = true;
}

Imath::V3f QuadPatch::position_world(float s, float t) const {
  return to_f(
      bilerp({to_d(m_p[0]), to_d(m_p[1]), to_d(m_p[2]), to_d(m_p[3])}, double(s), double(t)));
}

Imath::V2f QuadPatch::uv(float s, float t) const {
  const V2d c[4] = {V2d(m_uv[0].x, m_uv[0].y), V2d(m_uv[1].x, m_uv[1].y), V2d(m_uv[2].x, m_uv[2].y),
                    V2d(m_uv[3].x, m_uv[3].y)};
  const V2d r = bilerp(c, double(s), double(t));
  return Imath::V2f(float(r.x), float(r.y));
}

Imath::V3f QuadPatch::texture_point(float s, float t) const {
  const Imath::V2f uv_st = uv(s, t);
  return V3f(uv_st.x * m_repeats_per_uv * m_repeat_mm.x, uv_st.y * m_repeats_per_uv * m_repeat_mm.y,
             m_thickness_mm);
}

SurfaceFrame QuadPatch::frame(float s_f, float t_f) const {
  const double s = s_f, t = t_f;
  const V3d p[4] = {to_d(m_p[0]), to_d(m_p[1]), to_d(m_p[2]), to_d(m_p[3])};
  const V2d uv[4] = {V2d(m_uv[0].x, m_uv[0].y), V2d(m_uv[1].x, m_uv[1].y),
                     V2d(m_uv[2].x, m_uv[2].y), V2d(m_uv[3].x, m_uv[3].y)};

  // Jacobians: world per parameter, texture mm per parameter.
  V3d ps, pt;
  V2d us, ut;
  bilerp_derivatives(p, s, t, ps, pt);
  bilerp_derivatives(uv, s, t, us, ut);
  const double kx = double(m_repeats_per_uv) * m_repeat_mm.x;
  const double ky = double(m_repeats_per_uv) * m_repeat_mm.y;
  const double m00 = kx * us.x, m01 = kx * ut.x;  // d(texture x)/ds, /dt
  const double m10 = ky * us.y, m11 = ky * ut.y;  // d(texture y)/ds, /dt
  const double det = m00 * m11 - m01 * m10;

  // World tangents per texture mm: the columns of J * inverse(M).
  const V3d dp_dx = (ps * m11 - pt * m10) / det;
  const V3d dp_dy = (pt * m00 - ps * m01) / det;

  // Orthonormal frame: N across, T along texture x in the tangent plane.
  const V3d n = ps.cross(pt).normalized();
  const V3d tangent = (dp_dx - n * dp_dx.dot(n)).normalized();
  const V3d bitangent = n.cross(tangent);

  SurfaceFrame f;
  f.tangent_world = to_f(tangent);
  f.bitangent_world = to_f(bitangent);
  f.normal_world = to_f(n);
  f.mm_per_world = V3f(float(1.0 / dp_dx.dot(tangent)), float(1.0 / dp_dy.dot(bitangent)),
                       m_thickness_mm / m_thickness_world);
  return f;
}

bool QuadPatch::parameters_of(const Imath::V3f& p_world, float& s_out, float& t_out) const {
  if (!m_valid) return false;
  const V3d p[4] = {to_d(m_p[0]), to_d(m_p[1]), to_d(m_p[2]), to_d(m_p[3])};
  const V3d target = to_d(p_world);
  const double size = std::max((p[2] - p[0]).length(), (p[3] - p[1]).length());

  // Gauss-Newton on |P(s, t) - target|^2 from the centre; converged when the
  // step moves the point by a tiny fraction of the patch size.
  double s = 0.5, t = 0.5;
  bool converged = false;
  for (int iter = 0; iter < 30 && !converged; ++iter) {
    const V3d r = bilerp(p, s, t) - target;
    V3d ps, pt;
    bilerp_derivatives(p, s, t, ps, pt);
    const double a = ps.dot(ps), b = ps.dot(pt), c = pt.dot(pt);
    const double det = a * c - b * b;
    if (!(det > 0.0)) return false;
    const double gs = ps.dot(r), gt = pt.dot(r);
    double ds = -(c * gs - b * gt) / det;
    double dt = -(a * gt - b * gs) / det;
    // Clamp the step: at most half the patch per iteration.
    const double longest = std::max(std::abs(ds), std::abs(dt));
    if (longest > 0.5) {
      ds *= 0.5 / longest;
      dt *= 0.5 / longest;
    }
    s = std::clamp(s + ds, -0.5, 1.5);
    t = std::clamp(t + dt, -0.5, 1.5);
    converged = (ps * ds + pt * dt).length() <= 1e-9 * size;
  }
  if (!converged) return false;
  if (s < -kEdgeEps || s > 1.0 + kEdgeEps || t < -kEdgeEps || t > 1.0 + kEdgeEps) return false;
  s_out = float(std::clamp(s, 0.0, 1.0));
  t_out = float(std::clamp(t, 0.0, 1.0));
  return true;
}

bool QuadPatch::intersect(const Ray& ray_world, float t_min, float t_max, PatchHit& hit) const {
  if (!m_valid) return false;
  const V3d d = to_d(ray_world.direction_world);
  const V3d origin = to_d(ray_world.origin_world);
  V3d q[4];
  for (int i = 0; i < 4; ++i) q[i] = to_d(m_p[i]) - origin;

  // Choose the family of rulings least parallel to the ray: the line solve
  // below divides by |d x ruling|^2. Rulings at constant s run along dP/dt,
  // rulings at constant t along dP/ds. With `swap` the roles of s and t trade.
  const V3d along_t = (q[3] - q[0]) + (q[2] - q[1]);
  const V3d along_s = (q[1] - q[0]) + (q[2] - q[3]);
  const bool swap =
      d.cross(along_t.normalized()).length2() < d.cross(along_s.normalized()).length2();
  // a00 -> a10 is the edge the ruling parameter u runs along; rulings go from
  // lerp(a00, a10, u) to lerp(a01, a11, u) with parameter v.
  const V3d& a00 = q[0];
  const V3d& a10 = swap ? q[3] : q[1];
  const V3d& a11 = q[2];
  const V3d& a01 = swap ? q[1] : q[3];
  const V3d e10 = a10 - a00, e00 = a01 - a00, e11 = a11 - a10;

  // Step 1: rulings coplanar with the ray: det(pa(u), d, pb(u)) = a + b u + c u^2.
  const double a = a00.cross(d).dot(e00);
  const double c = d.dot(e10.cross(e00 - e11));
  const double b = a10.cross(d).dot(e11) - a - c;  // from the value at u = 1
  double roots[2];
  const int n_roots = unit_roots(a, b, c, roots);

  // Step 2: for each ruling, where along it the ray crosses, and at what distance.
  bool found = false;
  double best_t = double(t_max), best_u = 0.0, best_v = 0.0;
  for (int i = 0; i < n_roots; ++i) {
    const double u = roots[i];
    const V3d pa = a00 + e10 * u;
    const V3d pb = e00 + (e11 - e00) * u;
    const V3d n = d.cross(pb);
    const double nn = n.length2();
    if (!(nn > 1e-24 * d.length2() * pb.length2())) continue;  // ray parallel to the ruling
    const double t_ray = pa.cross(pb).dot(n) / nn;
    const double v = pa.cross(d).dot(n) / nn;
    if (!(v >= -kEdgeEps && v <= 1.0 + kEdgeEps)) continue;
    if (!(t_ray > double(t_min) && t_ray < best_t)) continue;
    found = true;
    best_t = t_ray;
    best_u = u;
    best_v = v;
  }
  if (!found) return false;

  // Step 3: the hit record, in the patch's own (s, t) and orientation.
  const double s = std::clamp(swap ? best_v : best_u, 0.0, 1.0);
  const double t = std::clamp(swap ? best_u : best_v, 0.0, 1.0);
  V3d ps, pt;
  bilerp_derivatives(q, s, t, ps, pt);
  hit.t_world = float(best_t);
  if (!(hit.t_world > t_min && hit.t_world < t_max)) return false;  // lost to float rounding
  hit.s = float(s);
  hit.t = float(t);
  hit.front_facing = d.dot(ps.cross(pt)) < 0.0;
  return true;
}

}  // namespace clothbake
