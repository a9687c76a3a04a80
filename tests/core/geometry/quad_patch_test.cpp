// Tests of the map m (baker/core/geometry/quad_patch.h), PAPER.md s.4: the bilinear
// patch, its exact ray intersection, its inverse and its local frame.
//
// Tolerances: inputs are floats (relative rounding 6e-8); the patch code works
// in double, so parameters and distances are good to ~1e-6 even for twisted
// quads. The bounds below (1e-5 for parameters, 1e-4 relative for distances,
// 1e-6 for orthonormality) leave a margin of 10x or more, yet a wrong formula
// (swapped corners, a missed root, a wrong scale) misses them by orders.

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/geometry/quad_patch.h"
#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V2f;
using Imath::V3d;
using Imath::V3f;

constexpr float kRepeats = 2.0f;
const V2f kRepeatMm(3.0f, 4.5f);
constexpr float kThicknessMm = 1.5f;
constexpr float kThicknessWorld = 0.05f;
constexpr float kInf = std::numeric_limits<float>::infinity();

/// A one-quad mesh with the given corners and UVs, as a patch.
QuadPatch make_patch(const V3f (&p)[4], const V2f (&uv)[4],
                     float thickness_world = kThicknessWorld) {
  QuadMesh mesh;
  for (int i = 0; i < 4; ++i) {
    mesh.positions_world.push_back(p[i]);
    mesh.uvs.push_back(uv[i]);
  }
  mesh.quads.push_back({{0, 1, 2, 3}, {0, 1, 2, 3}});
  return QuadPatch(mesh, 0, kRepeats, kRepeatMm, kThicknessMm, thickness_world);
}

constexpr V2f kUnitUv[4] = {V2f(0, 0), V2f(1, 0), V2f(1, 1), V2f(0, 1)};

/// A parallelogram in a tilted plane, non-orthogonal edges.
const V3f kP0(0.3f, -0.2f, 0.5f), kE1(1.2f, 0.4f, -0.3f), kE3(0.5f, 0.9f, 0.6f);
QuadPatch parallelogram(const V2f (&uv)[4]) {
  return make_patch({kP0, kP0 + kE1, kP0 + kE1 + kE3, kP0 + kE3}, uv);
}

/// A planar convex quad that is not a parallelogram (the ray quadratic stays quadratic).
QuadPatch planar_trapezoid() {
  const V3f a(1, 0, 0), b(0.3f, 0.8f, 0.5f);  // in-plane axes
  const V3f o(-0.4f, 0.2f, 0.1f);
  return make_patch({o, o + a * 1.5f, o + a * 1.1f + b * 0.9f, o + a * 0.2f + b * 1.2f}, kUnitUv);
}

/// Unit square (edge 1) with corner 2 lifted by `lift` along the normal.
QuadPatch twisted(float lift) {
  return make_patch({V3f(0, 0, 0), V3f(1, 0, 0), V3f(1, 1, lift), V3f(0, 1, 0)}, kUnitUv);
}

/// A strongly non-planar quad in general position: corner 2 lifted by 50% of
/// the edge length out of a rotated, sheared square.
QuadPatch twisted_general() {
  const V3f e1(0.8f, 0.5f, 0.2f), e3(-0.4f, 0.7f, 0.45f);
  const V3f n = e1.cross(e3).normalized();
  const V3f o(2.0f, -1.0f, 0.5f);
  const V2f uv[4] = {V2f(0.2f, 0.1f), V2f(0.7f, 0.15f), V2f(0.8f, 0.6f), V2f(0.1f, 0.5f)};
  return make_patch({o, o + e1, o + e1 + e3 + n * (0.5f * e1.length()), o + e3}, uv);
}

double max_abs(const V3f& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

// For a planar parallelogram with affine UVs, texture_point is an affine
// function of position, and the frame is the same everywhere.
TEST(QuadPatch, PlanarParallelogramMapsAffinely) {
  const V2f u0(0.1f, 0.2f), du(0.5f, 0.1f), dv(-0.05f, 0.4f);
  const QuadPatch patch = parallelogram({u0, u0 + du, u0 + du + dv, u0 + dv});
  ASSERT_TRUE(patch.valid());

  // A (2x3) = Tex (E^T E)^-1 E^T from the two edges E = [e1 e3].
  const V3d e1(kE1.x, kE1.y, kE1.z), e3(kE3.x, kE3.y, kE3.z);
  const V3f tex0 = patch.texture_point(0, 0);
  const V3f tex1 = patch.texture_point(1, 0) - tex0, tex3 = patch.texture_point(0, 1) - tex0;
  const double g11 = e1.dot(e1), g13 = e1.dot(e3), g33 = e3.dot(e3), det = g11 * g33 - g13 * g13;
  const auto apply_a = [&](const V3d& w) {  // A w, via the Gram inverse
    const double c1 = (g33 * e1.dot(w) - g13 * e3.dot(w)) / det;
    const double c3 = (g11 * e3.dot(w) - g13 * e1.dot(w)) / det;
    return V3d(c1 * tex1.x + c3 * tex3.x, c1 * tex1.y + c3 * tex3.y, 0.0);
  };

  const SurfaceFrame f0 = patch.frame(0.5f, 0.5f);
  Rng rng(7);
  for (int i = 0; i < 64; ++i) {
    const float s = rng.next_float(), t = rng.next_float();
    const V3f w = patch.position_world(s, t) - patch.position_world(0, 0);
    const V3d expect = apply_a(V3d(w.x, w.y, w.z));
    const V3f got = patch.texture_point(s, t) - tex0;
    EXPECT_NEAR(got.x, expect.x, 1e-5) << s << " " << t;
    EXPECT_NEAR(got.y, expect.y, 1e-5) << s << " " << t;
    EXPECT_EQ(patch.texture_point(s, t).z, kThicknessMm);

    const SurfaceFrame f = patch.frame(s, t);
    EXPECT_LT(max_abs(f.tangent_world - f0.tangent_world), 1e-6);
    EXPECT_LT(max_abs(f.bitangent_world - f0.bitangent_world), 1e-6);
    EXPECT_LT(max_abs(f.normal_world - f0.normal_world), 1e-6);
    EXPECT_LT(max_abs(f.mm_per_world - f0.mm_per_world), 1e-5);
  }

  // The frame's scales are those of A: A T = (mm.x, 0), (A B).y = mm.y.
  const V3f& t_w = f0.tangent_world;
  const V3f& b_w = f0.bitangent_world;
  const V3d at = apply_a(V3d(t_w.x, t_w.y, t_w.z)), ab = apply_a(V3d(b_w.x, b_w.y, b_w.z));
  EXPECT_NEAR(at.x, f0.mm_per_world.x, 1e-5);
  EXPECT_NEAR(at.y, 0.0, 1e-5);
  EXPECT_NEAR(ab.y, f0.mm_per_world.y, 1e-5);
  EXPECT_NEAR(f0.mm_per_world.z, kThicknessMm / kThicknessWorld, 1e-4);
}

// A rectangle with axis-aligned UVs: mm_per_world is repeat size over edge length.
TEST(QuadPatch, RectangleScalesMatchEdgeLengths) {
  const V3f x_axis = V3f(0.6f, 0.8f, 0.0f), y_axis = V3f(0.0f, 0.0f, 1.0f);  // unit, orthogonal
  const float length = 2.0f, width = 0.5f;
  const V3f o(1, 2, 3);
  const QuadPatch patch = make_patch(
      {o, o + x_axis * length, o + x_axis * length + y_axis * width, o + y_axis * width}, kUnitUv);
  ASSERT_TRUE(patch.valid());
  for (float s : {0.0f, 0.3f, 1.0f}) {
    const SurfaceFrame f = patch.frame(s, 1.0f - s);
    EXPECT_NEAR(f.mm_per_world.x, kRepeats * kRepeatMm.x / length, 1e-6);
    EXPECT_NEAR(f.mm_per_world.y, kRepeats * kRepeatMm.y / width, 1e-6);
    EXPECT_LT(max_abs(f.tangent_world - x_axis), 1e-6);
    EXPECT_LT(max_abs(f.bitangent_world - y_axis), 1e-6);
    EXPECT_LT(max_abs(f.normal_world - x_axis.cross(y_axis)), 1e-6);
    // The whole edge carries the whole texture extent.
    const V3f edge_mm = f.texture_from_world(x_axis * length);
    EXPECT_NEAR(edge_mm.x, kRepeats * kRepeatMm.x, 1e-5);
    EXPECT_NEAR(edge_mm.y, 0.0f, 1e-6);
  }
}

TEST(QuadPatch, ParametersOfRoundTrips) {
  const V2f u0(0.1f, 0.2f), du(0.5f, 0.1f), dv(-0.05f, 0.4f);
  const QuadPatch patches[] = {parallelogram({u0, u0 + du, u0 + du + dv, u0 + dv}),
                               planar_trapezoid(), twisted(0.5f), twisted_general()};
  Rng rng(11);
  for (const QuadPatch& patch : patches) {
    ASSERT_TRUE(patch.valid());
    for (int i = 0; i < 200; ++i) {
      const float s = rng.next_float(), t = rng.next_float();
      float s2 = -1, t2 = -1;
      ASSERT_TRUE(patch.parameters_of(patch.position_world(s, t), s2, t2)) << s << " " << t;
      EXPECT_NEAR(s2, s, 1e-5);
      EXPECT_NEAR(t2, t, 1e-5);
    }
    // Corners and edges too.
    for (float s : {0.0f, 1.0f})
      for (float t : {0.0f, 0.5f, 1.0f}) {
        float s2 = -1, t2 = -1;
        ASSERT_TRUE(patch.parameters_of(patch.position_world(s, t), s2, t2));
        EXPECT_NEAR(s2, s, 1e-5);
        EXPECT_NEAR(t2, t, 1e-5);
      }
  }
  // A point well outside the patch has no parameters in [0, 1]^2.
  float s2, t2;
  EXPECT_FALSE(twisted(0.5f).parameters_of(V3f(3.0f, 0.5f, 0.0f), s2, t2));
}

// A ray aimed at P(s, t) from a random origin on either side finds (s, t) at
// the right distance; with no distance window, the nearest hit is on the ray
// and no farther than P.
TEST(QuadPatch, IntersectRoundTrips) {
  const V2f u0(0.1f, 0.2f), du(0.5f, 0.1f), dv(-0.05f, 0.4f);
  const QuadPatch patches[] = {parallelogram({u0, u0 + du, u0 + du + dv, u0 + dv}),
                               planar_trapezoid(), twisted(0.5f), twisted_general()};
  Rng rng(23);
  for (const QuadPatch& patch : patches) {
    ASSERT_TRUE(patch.valid());
    int front = 0, back = 0;
    for (int i = 0; i < 300; ++i) {
      const float s = rng.next_float(), t = rng.next_float();
      const V3f p = patch.position_world(s, t);
      const V3f n = patch.frame(s, t).normal_world;
      // A random direction at least ~12 degrees off the tangent plane.
      V3f w;
      do {
        w = V3f(rng.next_float() * 2 - 1, rng.next_float() * 2 - 1, rng.next_float() * 2 - 1);
      } while (w.length2() > 1.0f || w.length2() < 1e-2f || std::abs(w.normalized().dot(n)) < 0.2f);
      w.normalize();
      const float dist = 0.5f + 4.0f * rng.next_float();
      const Ray ray{p + w * dist, -w};
      const float dist_exact = (p - ray.origin_world).length();

      PatchHit hit;
      ASSERT_TRUE(patch.intersect(ray, dist_exact * 0.999f, dist_exact * 1.001f, hit))
          << s << " " << t;
      EXPECT_NEAR(hit.s, s, 1e-4);
      EXPECT_NEAR(hit.t, t, 1e-4);
      EXPECT_NEAR(hit.t_world, dist_exact, 1e-4 * dist_exact);
      EXPECT_EQ(hit.front_facing, w.dot(n) > 0.0f);
      (hit.front_facing ? front : back)++;

      PatchHit nearest;
      ASSERT_TRUE(patch.intersect(ray, 0.0f, kInf, nearest));
      EXPECT_LE(nearest.t_world, dist_exact * (1 + 1e-4f));
      const V3f on_patch = patch.position_world(nearest.s, nearest.t);
      EXPECT_LT(max_abs(on_patch - (ray.origin_world + ray.direction_world * nearest.t_world)),
                1e-4 * dist_exact);
    }
    EXPECT_GT(front, 50);
    EXPECT_GT(back, 50);
  }
}

TEST(QuadPatch, FramesAreOrthonormalOnTwistedQuads) {
  const QuadPatch patches[] = {twisted(0.5f), twisted_general()};
  Rng rng(5);
  for (const QuadPatch& patch : patches) {
    ASSERT_TRUE(patch.valid());
    for (int i = 0; i < 200; ++i) {
      const float s = rng.next_float(), t = rng.next_float();
      const SurfaceFrame f = patch.frame(s, t);
      const V3f &T = f.tangent_world, &B = f.bitangent_world, &N = f.normal_world;
      EXPECT_NEAR(T.length(), 1.0f, 1e-6);
      EXPECT_NEAR(B.length(), 1.0f, 1e-6);
      EXPECT_NEAR(N.length(), 1.0f, 1e-6);
      EXPECT_LT(std::abs(T.dot(B)), 1e-6);
      EXPECT_LT(std::abs(T.dot(N)), 1e-6);
      EXPECT_LT(std::abs(B.dot(N)), 1e-6);
      EXPECT_LT(max_abs(T.cross(B) - N), 1e-6);  // right-handed
      EXPECT_GT(f.mm_per_world.x, 0.0f);
      EXPECT_GT(f.mm_per_world.y, 0.0f);
      for (const V3f& d : {V3f(1, 0, 0), V3f(0.3f, -2.0f, 0.7f), V3f(-0.1f, 0.2f, -5.0f)}) {
        const V3f back = f.texture_from_world(f.world_from_texture(d));
        EXPECT_LT(max_abs(back - d), 1e-5 * d.length());
      }
    }
  }
}

// The normal of a non-planar quad varies and matches the finite-difference
// normal; T follows the texture x direction (here the s direction).
TEST(QuadPatch, TwistedNormalsMatchFiniteDifferences) {
  const QuadPatch patch = twisted(0.5f);
  ASSERT_TRUE(patch.valid());
  const float h = 1e-3f;
  for (float s : {0.1f, 0.5f, 0.9f})
    for (float t : {0.1f, 0.5f, 0.9f}) {
      const V3f ds = patch.position_world(s + h, t) - patch.position_world(s - h, t);
      const V3f dt = patch.position_world(s, t + h) - patch.position_world(s, t - h);
      const V3f n_fd = ds.cross(dt).normalized();
      const SurfaceFrame f = patch.frame(s, t);
      EXPECT_LT(max_abs(f.normal_world - n_fd), 1e-3) << s << " " << t;
      const V3f ds_tangent = (ds - n_fd * ds.dot(n_fd)).normalized();
      EXPECT_LT(max_abs(f.tangent_world - ds_tangent), 1e-3) << s << " " << t;
    }
  // Exact value for z = 0.5 s t: N ~ (-0.5 t, -0.5 s, 1).
  EXPECT_LT(max_abs(patch.frame(1, 1).normal_world - V3f(-0.5f, -0.5f, 1).normalized()), 1e-6);
  EXPECT_GT(std::acos(patch.frame(0, 0).normal_world.dot(patch.frame(1, 1).normal_world)), 0.5);
}

TEST(QuadPatch, MirroredUvsGiveNegativeBitangentScale) {
  const V2f mirrored[4] = {V2f(0, 1), V2f(1, 1), V2f(1, 0), V2f(0, 0)};  // v runs against t
  const QuadPatch patch =
      make_patch({V3f(0, 0, 0), V3f(2, 0, 0), V3f(2, 1, 0), V3f(0, 1, 0)}, mirrored);
  ASSERT_TRUE(patch.valid());
  const SurfaceFrame f = patch.frame(0.4f, 0.7f);
  EXPECT_NEAR(f.mm_per_world.x, kRepeats * kRepeatMm.x / 2.0f, 1e-6);
  EXPECT_NEAR(f.mm_per_world.y, -kRepeats * kRepeatMm.y, 1e-5);
  EXPECT_LT(max_abs(f.normal_world - V3f(0, 0, 1)), 1e-6);  // geometry, not UVs, sets N
  EXPECT_LT(max_abs(f.bitangent_world - V3f(0, 1, 0)), 1e-6);
  // Moving up the quad (+B) moves down the texture.
  EXPECT_LT(f.texture_from_world(V3f(0, 1, 0)).y, 0.0f);
  EXPECT_LT(patch.texture_point(0.4f, 0.8f).y, patch.texture_point(0.4f, 0.7f).y);
}

const V3f kSquare[4] = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(1, 1, 0), V3f(0, 1, 0)};

TEST(QuadPatch, RayParallelToPlanarQuadMisses) {
  const QuadPatch patches[] = {make_patch(kSquare, kUnitUv), planar_trapezoid()};
  for (const QuadPatch& patch : patches) {
    ASSERT_TRUE(patch.valid());
    const SurfaceFrame f = patch.frame(0.5f, 0.5f);
    const V3f centre = patch.position_world(0.5f, 0.5f);
    for (float height : {0.1f, -0.1f, 1e-4f})
      for (float angle = 0.0f; angle < 6.3f; angle += 0.25f) {
        const V3f dir = f.tangent_world * std::cos(angle) + f.bitangent_world * std::sin(angle);
        const Ray ray{centre + f.normal_world * height - dir * 3.0f, dir.normalized()};
        PatchHit hit;
        EXPECT_FALSE(patch.intersect(ray, 0.0f, kInf, hit)) << height << " " << angle;
      }
    // Along the edge directions exactly (the degenerate ruling case).
    for (int i = 0; i < 4; ++i) {
      const V3f dir = (patch.corner_world((i + 1) % 4) - patch.corner_world(i)).normalized();
      const Ray ray{centre + f.normal_world * 0.1f - dir * 3.0f, dir};
      PatchHit hit;
      EXPECT_FALSE(patch.intersect(ray, 0.0f, kInf, hit));
    }
  }
}

TEST(QuadPatch, RaysThroughEdgesAndCornersHit) {
  const QuadPatch patch = make_patch(kSquare, kUnitUv);
  const struct {
    V3f target;
    float s, t;
  } cases[] = {{V3f(0.5f, 0, 0), 0.5f, 0},   {V3f(1, 0.25f, 0), 1, 0.25f},
               {V3f(0.75f, 1, 0), 0.75f, 1}, {V3f(0, 0.5f, 0), 0, 0.5f},
               {V3f(0, 0, 0), 0, 0},         {V3f(1, 1, 0), 1, 1}};
  for (const auto& c : cases)
    for (const V3f& offset : {V3f(0, 0, 2), V3f(0.3f, -0.2f, 1.5f), V3f(-0.7f, 0.4f, -1)}) {
      const Ray ray{c.target + offset, -offset.normalized()};
      PatchHit hit;
      ASSERT_TRUE(patch.intersect(ray, 0.0f, kInf, hit)) << c.s << " " << c.t;
      EXPECT_NEAR(hit.s, c.s, 1e-6);
      EXPECT_NEAR(hit.t, c.t, 1e-6);
      EXPECT_NEAR(hit.t_world, offset.length(), 1e-6);
      EXPECT_GE(hit.s, 0.0f);
      EXPECT_LE(hit.s, 1.0f);
      EXPECT_GE(hit.t, 0.0f);
      EXPECT_LE(hit.t, 1.0f);
    }
  // Just outside an edge: miss.
  PatchHit hit;
  EXPECT_FALSE(patch.intersect(Ray{V3f(1.001f, 0.5f, 1), V3f(0, 0, -1)}, 0.0f, kInf, hit));
}

TEST(QuadPatch, DistanceWindowAndFacing) {
  const QuadPatch patch = make_patch(kSquare, kUnitUv);
  PatchHit hit;
  const Ray down{V3f(0.3f, 0.6f, 2), V3f(0, 0, -1)};
  ASSERT_TRUE(patch.intersect(down, 0.0f, kInf, hit));
  EXPECT_TRUE(hit.front_facing);  // counter-clockwise seen from +z: N = +z
  EXPECT_FLOAT_EQ(hit.t_world, 2.0f);
  const Ray up{V3f(0.3f, 0.6f, -2), V3f(0, 0, 1)};
  ASSERT_TRUE(patch.intersect(up, 0.0f, kInf, hit));
  EXPECT_FALSE(hit.front_facing);

  // Behind the origin, before t_min, after t_max: no hit.
  EXPECT_FALSE(patch.intersect(Ray{V3f(0.3f, 0.6f, 2), V3f(0, 0, 1)}, 0.0f, kInf, hit));
  EXPECT_FALSE(patch.intersect(down, 2.5f, kInf, hit));
  EXPECT_FALSE(patch.intersect(down, 0.0f, 1.5f, hit));
  EXPECT_TRUE(patch.intersect(down, 1.5f, 2.5f, hit));
}

// z = s t over the unit square; the ray (l, l, l - 0.16) meets it at l = 0.2 and 0.8.
TEST(QuadPatch, TwistedQuadHitTwiceReportsNearest) {
  const QuadPatch patch = twisted(1.0f);
  ASSERT_TRUE(patch.valid());
  const V3f dir = V3f(1, 1, 1).normalized();
  const auto on_ray = [](float l) { return V3f(l, l, l - 0.16f); };
  const float sqrt3 = std::sqrt(3.0f);

  PatchHit hit;
  const Ray forward{on_ray(-0.5f), dir};
  ASSERT_TRUE(patch.intersect(forward, 0.0f, kInf, hit));
  EXPECT_NEAR(hit.s, 0.2f, 1e-5);
  EXPECT_NEAR(hit.t, 0.2f, 1e-5);
  EXPECT_NEAR(hit.t_world, 0.7f * sqrt3, 1e-5);
  EXPECT_FALSE(hit.front_facing);  // N(0.2, 0.2) ~ (-0.2, -0.2, 1): dot with dir > 0
  // Past the first hit: the second.
  ASSERT_TRUE(patch.intersect(forward, 0.8f * sqrt3, kInf, hit));
  EXPECT_NEAR(hit.s, 0.8f, 1e-5);
  EXPECT_NEAR(hit.t_world, 1.3f * sqrt3, 1e-5);
  EXPECT_TRUE(hit.front_facing);  // N(0.8, 0.8) ~ (-0.8, -0.8, 1): dot with dir < 0

  const Ray backward{on_ray(1.5f), -dir};
  ASSERT_TRUE(patch.intersect(backward, 0.0f, kInf, hit));
  EXPECT_NEAR(hit.s, 0.8f, 1e-5);
  EXPECT_NEAR(hit.t, 0.8f, 1e-5);
  EXPECT_NEAR(hit.t_world, 0.7f * sqrt3, 1e-5);
  EXPECT_FALSE(hit.front_facing);
}

TEST(QuadPatch, DegenerateQuadsAreInvalid) {
  ASSERT_TRUE(make_patch(kSquare, kUnitUv).valid());  // the builder itself is fine

  const V3f collinear[4] = {V3f(0, 0, 0), V3f(1, 1, 1), V3f(2, 2, 2), V3f(3, 3, 3)};
  EXPECT_FALSE(make_patch(collinear, kUnitUv).valid());
  const V3f duplicate[4] = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(1, 1, 0), V3f(1, 1, 0)};
  EXPECT_FALSE(make_patch(duplicate, kUnitUv).valid());
  const V3f point[4] = {V3f(1, 2, 3), V3f(1, 2, 3), V3f(1, 2, 3), V3f(1, 2, 3)};
  EXPECT_FALSE(make_patch(point, kUnitUv).valid());
  const V3f bowtie[4] = {V3f(0, 0, 0), V3f(1, 0, 0), V3f(0, 1, 0), V3f(1, 1, 0)};  // folded
  EXPECT_FALSE(make_patch(bowtie, kUnitUv).valid());

  const V2f flat_uv[4] = {V2f(0, 0), V2f(1, 0.5f), V2f(2, 1), V2f(1, 0.5f)};
  EXPECT_FALSE(make_patch(kSquare, flat_uv).valid());
  const V2f same_uv[4] = {V2f(0.5f, 0.5f), V2f(0.5f, 0.5f), V2f(0.5f, 0.5f), V2f(0.5f, 0.5f)};
  EXPECT_FALSE(make_patch(kSquare, same_uv).valid());
  EXPECT_FALSE(make_patch(kSquare, kUnitUv, 0.0f).valid());  // zero thickness

  // An invalid patch is never hit, even by a ray through its corners' hull.
  PatchHit hit;
  EXPECT_FALSE(make_patch(duplicate, kUnitUv)
                   .intersect(Ray{V3f(0.6f, 0.3f, 1), V3f(0, 0, -1)}, 0.0f, kInf, hit));
  QuadMesh empty;
  EXPECT_FALSE(QuadPatch(empty, 0, 1.0f, V2f(1, 1), 1.0f, 1.0f).valid());
}

TEST(QuadPatch, BoundsAreTheCornersBox) {
  const QuadPatch patch = twisted_general();
  V3f lo = patch.corner_world(0), hi = lo;
  for (int i = 1; i < 4; ++i) {
    const V3f& c = patch.corner_world(i);
    lo = V3f(std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z));
    hi = V3f(std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z));
  }
  EXPECT_EQ(patch.bounds_min_world(), lo);
  EXPECT_EQ(patch.bounds_max_world(), hi);
  Rng rng(3);
  for (int i = 0; i < 100; ++i) {
    const V3f p = patch.position_world(rng.next_float(), rng.next_float());
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p[k], lo[k]);
      EXPECT_LE(p[k], hi[k]);
    }
  }
}

}  // namespace
}  // namespace clothbake
