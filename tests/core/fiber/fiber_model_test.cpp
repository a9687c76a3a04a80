// Tests of the fibre reflection model (baker/core/fiber/fiber_model.h), PAPER.md s.3.
//
// Statistical tolerances come from the sample count: a mean of N values in
// [0, 1] with true mean mu has standard deviation at most sqrt(mu (1 - mu) / N)
// (a [0,1] variable has variance <= mu (1 - mu)); tests allow 4 of those. The
// stratified jitter makes the real error far smaller, so these bounds are safe
// yet still fail on a wrong formula (see each test).

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/fiber/fiber_model.h"
#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

/// Unit vector at polar angle `theta` from +z and azimuth `phi` about it.
V3f polar(double theta, double phi) {
  return V3f(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
             float(std::cos(theta)));
}

/// Four-sigma bound for the mean of `n` values in [0, 1] whose true mean is `mu`.
double four_sigma(double mu, int n) { return 4.0 * std::sqrt(std::max(mu * (1.0 - mu), 0.0) / n); }

TEST(FiberClosedForms, KnownValues) {
  EXPECT_NEAR(sphere_diffuse_exact(0.0), 2.0 / 3.0, 1e-12);  // mean of n.E over a disk
  EXPECT_NEAR(sphere_diffuse_exact(kPi / 2), 2.0 / (3.0 * kPi), 1e-12);
  EXPECT_NEAR(sphere_diffuse_exact(kPi), 0.0, 1e-12);
  EXPECT_NEAR(cylinder_diffuse_limit(kPi / 2, 0.0), kPi / 4, 1e-12);
  EXPECT_NEAR(cylinder_diffuse_limit(kPi / 2, kPi / 2), 0.25, 1e-12);
  EXPECT_NEAR(cylinder_diffuse_limit(kPi / 2, kPi), 0.0, 1e-12);
  EXPECT_NEAR(cylinder_diffuse_limit(kPi / 6, 0.0), 0.5 * kPi / 4, 1e-12);
}

// Aspect 1 is a sphere: the Lambert-sphere phase law. sigma <= sqrt(mu(1-mu))
// <= 0.5, so the bound is <= 4 * 0.5 / 64 = 0.031 (measured error: < 7e-4).
// The wrong law (2/3) cos a differs by 0.07 .. 0.67 at 60 .. 179 deg, so it fails.
TEST(EllipsoidFiber, SphereMatchesLambertPhaseLaw) {
  const int n = 4096;
  EllipsoidFiberParams params;
  params.aspect = 1.0f;
  params.samples = n;
  for (double deg : {0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 179.0}) {
    const double exact = sphere_diffuse_exact(deg * kDeg);
    for (uint64_t seed : {1u, 2u, 3u}) {
      // L generic, E at the phase angle from it; the tangent is irrelevant at aspect 1.
      const V3f light = polar(0.4, 0.1);
      const V3f side = light.cross(V3f(0, 0, 1)).normalized();
      const V3f eye = float(std::cos(deg * kDeg)) * light + float(std::sin(deg * kDeg)) * side;
      const FiberResponse r = ellipsoid_fiber(V3f(0.3f, -0.5f, 0.8f), light, eye, params, seed);
      EXPECT_NEAR(r.diffuse, exact, four_sigma(exact, n)) << "phase " << deg << " seed " << seed;
    }
  }
}

// L = E on a sphere: R.E = 1 - 2 r^2 over the unit disk, so the Phong mean is
// exactly 1 / (2 (n + 1)) and its second moment 1 / (2 (2n + 1)), which gives
// the exact per-sample sigma. A spec computed with R.L or without the n.L > 0
// gate would be 1/(n+1) or similar and fail.
TEST(EllipsoidFiber, SphereSpecularAtZeroPhaseMatchesClosedForm) {
  const int n = 4096;
  for (float exponent : {1.0f, 20.0f, 100.0f}) {
    EllipsoidFiberParams params;
    params.aspect = 1.0f;
    params.samples = n;
    params.exponent = exponent;
    const double mean = 1.0 / (2.0 * (exponent + 1.0));
    const double sigma = std::sqrt(1.0 / (2.0 * (2.0 * exponent + 1.0)) - mean * mean);
    const V3f dir = polar(1.1, -2.0);
    const FiberResponse r = ellipsoid_fiber(V3f(1, 0, 0), dir, dir, params, 5);
    EXPECT_NEAR(r.specular, mean, 4.0 * sigma / std::sqrt(double(n))) << "n = " << exponent;
    EXPECT_NEAR(r.diffuse, 2.0 / 3.0, four_sigma(2.0 / 3.0, n));
  }
}

// A long spheroid tends to the cylinder law. The ends' share of the projected
// area and their tilted normals make the gap fall as ~1/aspect^2 (measured: x8-9
// from aspect 10 to 30). With N = 2^18 stratified samples the MC noise measured
// at aspect 1000 (where the gap is < 1e-6) is ~1e-5, below the gaps compared.
TEST(EllipsoidFiber, ApproachesCylinderLimitAsAspectGrows) {
  struct Config {
    double theta_light, azimuth, theta_eye;  // degrees
  };
  const Config configs[] = {{90, 0, 90}, {45, 120, 60}, {120, 90, 50}, {30, 20, 45}};
  const V3f axis = polar(0.7, 2.0);                        // a generic axis ...
  const V3f side = axis.cross(V3f(0, 0, 1)).normalized();  // ... and a frame around it
  const V3f third = axis.cross(side);
  auto around_axis = [&](double theta, double phi) {
    const V3f p = polar(theta, phi);
    return p.x * side + p.y * third + p.z * axis;
  };
  for (const Config& c : configs) {
    const double limit = cylinder_diffuse_limit(c.theta_light * kDeg, c.azimuth * kDeg);
    const V3f light = around_axis(c.theta_light * kDeg, 0.3);
    const V3f eye = around_axis(c.theta_eye * kDeg, 0.3 + c.azimuth * kDeg);
    std::vector<double> error;
    for (float aspect : {10.0f, 30.0f, 100.0f, 300.0f}) {
      EllipsoidFiberParams params;
      params.aspect = aspect;
      params.samples = 1 << 18;
      error.push_back(std::abs(ellipsoid_fiber(axis, light, eye, params, 11).diffuse - limit));
    }
    SCOPED_TRACE(testing::Message() << "theta_L " << c.theta_light << " D " << c.azimuth
                                    << " theta_E " << c.theta_eye);
    EXPECT_GT(error[0], error[1]);
    EXPECT_GT(error[1], error[2]);
    EXPECT_GT(error[2], error[3]);
    // Aspect-10 gaps are <= 9e-3, so ~1/aspect^2 predicts <= 9e-5 at aspect 100;
    // 3e-4 leaves x3 for noise and higher-order terms (PAPER.md: ~3% at aspect 60).
    EXPECT_LT(error[2], 3e-4);
    EXPECT_GT(error[0], 1e-3);  // the test sees a real gap at aspect 10, not just noise
  }
}

// On a long fibre the highlight lies on the cone theta_E = pi - theta_L. Off the
// cone by 60 deg the Phong lobe is cos(60)^20 ~ 1e-6 of its peak.
TEST(EllipsoidFiber, SpecularLiesOnTheMirrorCone) {
  EllipsoidFiberParams params;
  params.aspect = 100.0f;
  params.samples = 4096;
  const V3f axis(0, 0, 1), light = polar(60 * kDeg, 0.0);
  const FiberResponse on = ellipsoid_fiber(axis, light, polar(120 * kDeg, 0.0), params, 1);
  const FiberResponse off = ellipsoid_fiber(axis, light, polar(60 * kDeg, 0.0), params, 1);
  EXPECT_GT(on.specular, 0.05f);
  EXPECT_LT(off.specular, 1e-3f);
}

TEST(EllipsoidFiber, SameSeedSameBitsOtherSeedOtherPattern) {
  EllipsoidFiberParams params;
  params.samples = 16;
  const V3f t(0.2f, 0.9f, 0.1f), l = polar(0.8, 0.3), e = polar(1.2, 2.0);
  const FiberResponse a = ellipsoid_fiber(t, l, e, params, 42);
  const FiberResponse b = ellipsoid_fiber(t, l, e, params, 42);
  const FiberResponse c = ellipsoid_fiber(t, l, e, params, 43);
  EXPECT_EQ(a.diffuse, b.diffuse);
  EXPECT_EQ(a.specular, b.specular);
  EXPECT_NE(a.diffuse, c.diffuse);
}

TEST(EllipsoidFiber, SampleCountRoundsUpToASquare) {
  EllipsoidFiberParams ten, sixteen;
  ten.samples = 10;
  sixteen.samples = 16;
  const V3f t(1, 2, 3), l = polar(0.5, 0.0), e = polar(1.0, 1.0);
  const FiberResponse a = ellipsoid_fiber(t, l, e, ten, 9);
  const FiberResponse b = ellipsoid_fiber(t, l, e, sixteen, 9);
  EXPECT_EQ(a.diffuse, b.diffuse);
  EXPECT_EQ(a.specular, b.specular);
}

// The spheroid does not know which way its axis points; the implementation
// makes that exact (same bits), including the case v perpendicular to E.
TEST(EllipsoidFiber, AxisSignGivesIdenticalBits) {
  EllipsoidFiberParams params;
  params.samples = 64;
  for (uint64_t i = 0; i < 200; ++i) {
    Rng rng(hash_key(77, i));
    const V3f t = polar(std::acos(2 * rng.next_double() - 1), 2 * kPi * rng.next_double());
    const V3f l = polar(std::acos(2 * rng.next_double() - 1), 2 * kPi * rng.next_double());
    const V3f e = i % 4 == 0 ? t.cross(l) : polar(std::acos(2 * rng.next_double() - 1), 1.0);
    const FiberResponse a = ellipsoid_fiber(t, l, e, params, i);
    const FiberResponse b = ellipsoid_fiber(-t, l, e, params, i);
    ASSERT_EQ(a.diffuse, b.diffuse) << i;
    ASSERT_EQ(a.specular, b.specular) << i;
  }
}

// Only directions matter: scaling inputs changes nothing beyond float rounding
// of the normalisation (a few ulp of the angles, so ~1e-6 in the means).
TEST(EllipsoidFiber, InputsAreNormalised) {
  EllipsoidFiberParams params;
  const V3f t(0.3f, 0.1f, 0.9f), l = polar(0.7, 0.2), e = polar(1.3, 2.5);
  const FiberResponse a = ellipsoid_fiber(t, l, e, params, 3);
  const FiberResponse b = ellipsoid_fiber(t * 1e-3f, l * 3.7f, e * 250.0f, params, 3);
  EXPECT_NEAR(a.diffuse, b.diffuse, 1e-5);
  EXPECT_NEAR(a.specular, b.specular, 1e-5);
}

TEST(EllipsoidFiber, ZeroTangentIsASphere) {
  const int n = 4096;
  EllipsoidFiberParams params;
  params.aspect = 8.0f;  // ignored: no axis
  params.samples = n;
  for (double deg : {0.0, 70.0, 140.0}) {
    const double exact = sphere_diffuse_exact(deg * kDeg);
    const FiberResponse r =
        ellipsoid_fiber(V3f(0.0f), polar(0.2, 0.0), polar(0.2 + deg * kDeg, 0.0), params, 4);
    EXPECT_NEAR(r.diffuse, exact, four_sigma(exact, n)) << deg;
  }
}

TEST(KajiyaKay, HandComputedValues) {
  const V3f t(0, 0, 1);
  // L and E perpendicular to t: diffuse pi/4, on the cone (theta_L + theta_E = pi).
  FiberResponse r = kajiya_kay_fiber(t, V3f(1, 0, 0), V3f(0, 1, 0), 20.0f);
  EXPECT_NEAR(r.diffuse, kPi / 4, 1e-6);
  EXPECT_NEAR(r.specular, 1.0, 1e-6);
  // theta_L = 60, theta_E = 90: sin60 sin90 - cos60 cos90 = sqrt(3)/2, squared = 3/4.
  r = kajiya_kay_fiber(t, polar(60 * kDeg, 0.0), polar(90 * kDeg, 1.0), 2.0f);
  EXPECT_NEAR(r.diffuse, kPi / 4 * std::sqrt(3.0) / 2, 1e-6);
  EXPECT_NEAR(r.specular, 0.75, 1e-6);
  // theta_L = 60, theta_E = 30: sin60 sin30 - cos60 cos30 = 0, no highlight.
  r = kajiya_kay_fiber(t, polar(60 * kDeg, 0.0), polar(30 * kDeg, 2.0), 2.0f);
  EXPECT_NEAR(r.specular, 0.0, 1e-6);
  // theta_L = 45, theta_E = 120: sin45 sin120 - cos45 cos120 = cos(15 deg).
  r = kajiya_kay_fiber(t, polar(45 * kDeg, 0.0), polar(120 * kDeg, 0.5), 10.0f);
  EXPECT_NEAR(r.specular, std::pow(std::cos(15 * kDeg), 10.0), 1e-5);
  // Axis sign does not matter.
  const FiberResponse flipped =
      kajiya_kay_fiber(-t, polar(45 * kDeg, 0.0), polar(120 * kDeg, 0.5), 10.0f);
  EXPECT_NEAR(flipped.specular, r.specular, 1e-6);
}

TEST(KajiyaKay, DiffuseIsTheCylinderLimitWhenAzimuthsAgree) {
  for (double deg : {10.0, 45.0, 90.0, 150.0}) {
    const FiberResponse r =
        kajiya_kay_fiber(V3f(0, 0, 1), polar(deg * kDeg, 0.4), polar(1.0, 0.4), 5.0f);
    EXPECT_NEAR(r.diffuse, cylinder_diffuse_limit(deg * kDeg, 0.0), 1e-6) << deg;
  }
}

// Degenerate geometry must give finite answers in [0, 1] for both direct models
// (the table has the same test in fiber_table_test.cpp).
TEST(FiberModels, DegenerateInputsGiveFiniteResponsesInRange) {
  const V3f t(0, 0, 1), x(1, 0, 0), y(0, 1, 0);
  struct Case {
    V3f tangent, light, eye;
  };
  const Case cases[] = {
      {t, t, t},
      {t, -t, t},
      {t, t, -t},
      {t, x, t},
      {t, t, x},
      {t, x, x},
      {t, x, -x},
      {t, x, y},
      {t, -t, -t},
      {t, V3f(1, 0, -1), V3f(0, 1, -2)},
      {V3f(0.0f), x, y},
      {V3f(0.0f), x, x},
      {V3f(0.0f), x, -x},
      {x, x, -x},
      {V3f(1e-30f, 0, 0), x, y},
      {V3f(1e30f, 1e30f, 0), V3f(0, 0, 1e-30f), V3f(3e30f, 0, 0)},
  };
  for (float aspect : {1.0f, 8.0f, 1e4f, 1e9f}) {
    for (int samples : {1, 16, 64}) {
      EllipsoidFiberParams params;
      params.aspect = aspect;
      params.samples = samples;
      for (size_t i = 0; i < std::size(cases); ++i) {
        const Case& c = cases[i];
        for (const FiberResponse r :
             {ellipsoid_fiber(c.tangent, c.light, c.eye, params, i),
              kajiya_kay_fiber(c.tangent, c.light, c.eye, params.exponent)}) {
          SCOPED_TRACE(testing::Message() << "case " << i << " aspect " << aspect);
          EXPECT_TRUE(std::isfinite(r.diffuse) && std::isfinite(r.specular));
          EXPECT_GE(r.diffuse, 0.0f);
          EXPECT_LE(r.diffuse, 1.0f);
          EXPECT_GE(r.specular, 0.0f);
          EXPECT_LE(r.specular, 1.0f);
        }
      }
    }
  }
}

TEST(FiberModels, NonFiniteOrZeroDirectionsGiveZero) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const V3f t(0, 0, 1), l(1, 0, 0), e(0, 1, 0);
  const V3f bad[] = {V3f(nan, 0, 0), V3f(0, inf, 0), V3f(0, 0, -inf)};
  EllipsoidFiberParams params;
  auto expect_zero = [](const FiberResponse& r) {
    EXPECT_EQ(r.diffuse, 0.0f);
    EXPECT_EQ(r.specular, 0.0f);
  };
  for (const V3f& b : bad) {
    expect_zero(ellipsoid_fiber(b, l, e, params, 1));
    expect_zero(ellipsoid_fiber(t, b, e, params, 1));
    expect_zero(ellipsoid_fiber(t, l, b, params, 1));
    expect_zero(kajiya_kay_fiber(b, l, e, 20.0f));
    expect_zero(kajiya_kay_fiber(t, l, b, 20.0f));
  }
  expect_zero(ellipsoid_fiber(t, V3f(0.0f), e, params, 1));
  expect_zero(ellipsoid_fiber(t, l, V3f(0.0f), params, 1));
  expect_zero(kajiya_kay_fiber(t, V3f(0.0f), e, 20.0f));
  // A NaN exponent or aspect in the parameters is also contained.
  params.exponent = nan;
  params.aspect = nan;
  const FiberResponse r = ellipsoid_fiber(t, l, e, params, 1);
  EXPECT_TRUE(std::isfinite(r.diffuse) && std::isfinite(r.specular));
}

}  // namespace
}  // namespace clothbake
