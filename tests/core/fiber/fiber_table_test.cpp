// Tests of the tabulated fibre model (baker/core/fiber/fiber_table.h): layout, accuracy
// against the direct ellipsoid model, symmetries, determinism, degenerate input.

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/util/error.h"
#include "core/fiber/fiber_table.h"
#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr double kPi = std::numbers::pi;

V3f polar(double theta, double phi) {
  return V3f(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
             float(std::cos(theta)));
}

V3f random_direction(Rng& rng) {
  return polar(std::acos(2.0 * rng.next_double() - 1.0), 2.0 * kPi * rng.next_double());
}

/// The default table, built once for the whole suite (~0.1-0.2 s).
const FiberTable& default_table() {
  static const FiberTable table = FiberTable::build(FiberTableParams{});
  return table;
}

TEST(FiberTable, EntryCountFollowsTheBins) {
  const FiberTable& table = default_table();
  EXPECT_EQ(table.entry_count(), size_t(25) * 48 * 48);  // theta_E gets 48/2 + 1
  EXPECT_EQ(table.diffuse_entries().size(), table.entry_count());
  EXPECT_EQ(table.specular_entries().size(), table.entry_count());
}

// Each entry is the direct model at its canonical grid node with seed
// hash_key(seed, canonical index) (same bits); equivalent nodes (undefined
// azimuth, the theta_E = pi/2 fold) share it. A lookup at a node, posed in a
// rotated frame, returns the entry up to the angles' float rounding: near the
// axis a float cosine resolves only ~3.5e-4 rad (0.5% of a bin), times
// neighbour steps <= 0.1, so 1e-3.
TEST(FiberTable, EntriesAndLookupsAtGridNodes) {
  const FiberTable& table = default_table();
  const FiberTableParams& p = table.params();
  const int n_l = p.theta_bins, n_e = p.theta_bins / 2 + 1, n_p = p.phi_bins;
  const V3f t = V3f(0.3f, -0.4f, 0.8f).normalized();  // a generic frame around t
  const V3f s = t.cross(V3f(1, 0, 0)).normalized(), r = t.cross(s);
  auto in_frame = [&](const V3f& a) { return a.x * s + a.y * r + a.z * t; };
  for (int i_e : {0, 1, 7, n_e - 2, n_e - 1}) {
    for (int i_l : {0, 3, 20, 30, n_l - 1}) {
      for (int i_p : {0, 5, 31, n_p - 1}) {
        const size_t index = (size_t(i_e) * n_l + i_l) * n_p + i_p;
        const int c_l = i_e == n_e - 1 ? std::min(i_l, n_l - 1 - i_l) : i_l;
        const int c_p = (i_e == 0 || c_l == 0 || c_l == n_l - 1) ? 0 : i_p;
        const size_t canonical = (size_t(i_e) * n_l + c_l) * n_p + c_p;
        const double th_e = i_e * kPi / 2 / (n_e - 1);
        const FiberResponse direct = ellipsoid_fiber(
            V3f(0, 0, 1), polar(c_l * kPi / (n_l - 1), 0.0), polar(th_e, c_p * kPi / (n_p - 1)),
            p.fiber, hash_key(p.seed, canonical));
        const V3f light = polar(i_l * kPi / (n_l - 1), 0.0),
                  eye = polar(th_e, i_p * kPi / (n_p - 1));
        SCOPED_TRACE(testing::Message() << i_e << " " << i_l << " " << i_p);
        EXPECT_EQ(table.diffuse_entries()[index], direct.diffuse);
        EXPECT_EQ(table.specular_entries()[index], direct.specular);
        const FiberResponse looked_up = table.eval(t, in_frame(light), in_frame(eye));
        EXPECT_NEAR(looked_up.diffuse, direct.diffuse, 1e-3);
        EXPECT_NEAR(looked_up.specular, direct.specular, 1e-3);
      }
    }
  }
}

// Table vs direct model over 500 random configurations (direct at N = 16384,
// whose own error is < 1e-3). Two errors add up:
//  - MC noise of the entries: each has 64 stratified samples; measured max error
//    of a single N = 64 evaluation over 500 configurations: 0.026 diffuse, 0.042
//    specular (interpolating 8 entries averages some of it away);
//  - trilinear interpolation over bins of ~3.75 deg: measured with noise-free
//    (N = 4096) entries: max 0.008 diffuse (where E is within ~1/aspect of the
//    axis and the end-on disc takes over within two bins), 0.003 specular.
// Measured over 2000 configurations: max 0.020 diffuse, 0.029 specular, mean
// 0.003 / 0.002. Tolerances: max 0.03 / 0.045, mean 0.006 / 0.005. A grid off by
// half a bin gives mean errors ~0.02, a swapped axis ~0.2, so both would fail.
TEST(FiberTable, MatchesTheDirectModel) {
  const FiberTable& table = default_table();
  EllipsoidFiberParams direct_params = table.params().fiber;
  direct_params.samples = 16384;
  const int count = 500;
  double max_d = 0, max_s = 0, sum_d = 0, sum_s = 0;
  for (int i = 0; i < count; ++i) {
    Rng rng(hash_key(2024, i));
    const V3f t = random_direction(rng), l = random_direction(rng), e = random_direction(rng);
    const FiberResponse direct = ellipsoid_fiber(t, l, e, direct_params, i);
    const FiberResponse looked_up = table.eval(t, l, e);
    const double d = std::abs(direct.diffuse - looked_up.diffuse);
    const double s = std::abs(direct.specular - looked_up.specular);
    max_d = std::max(max_d, d);
    max_s = std::max(max_s, s);
    sum_d += d;
    sum_s += s;
  }
  EXPECT_LT(max_d, 0.03);
  EXPECT_LT(max_s, 0.045);
  EXPECT_LT(sum_d / count, 0.006);
  EXPECT_LT(sum_s / count, 0.005);
}

TEST(FiberTable, BitIdenticalForAnyThreadCount) {
  FiberTableParams params;
  params.theta_bins = 24;
  params.phi_bins = 20;
  params.fiber.samples = 16;
  FiberTable one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = FiberTable::build(params);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = FiberTable::build(params);
  }
  const FiberTable again = FiberTable::build(params);
  EXPECT_EQ(one.diffuse_entries(), two.diffuse_entries());
  EXPECT_EQ(one.specular_entries(), two.specular_entries());
  EXPECT_EQ(one.diffuse_entries(), again.diffuse_entries());
  params.seed = 2;
  EXPECT_NE(FiberTable::build(params).diffuse_entries(), one.diffuse_entries());
}

// Flipping the axis and mirroring E through the (axis, L) plane are symmetries
// of the spheroid; the lookup makes both exact (same bits), which also checks
// that theta_E > pi/2 is folded onto the stored half.
TEST(FiberTable, AxisFlipAndAzimuthMirrorAreExact) {
  const FiberTable& table = default_table();
  for (int i = 0; i < 300; ++i) {
    Rng rng(hash_key(31, i));
    const V3f t = random_direction(rng), l = random_direction(rng), e = random_direction(rng);
    const FiberResponse a = table.eval(t, l, e);
    const FiberResponse flipped = table.eval(-t, l, e);
    // Mirror of E through the plane spanned by t and l.
    const V3f normal = t.cross(l).normalized();
    const V3f mirrored = e - 2.0f * e.dot(normal) * normal;
    const FiberResponse m = table.eval(t, l, mirrored);
    ASSERT_EQ(a.diffuse, flipped.diffuse) << i;
    ASSERT_EQ(a.specular, flipped.specular) << i;
    ASSERT_NEAR(a.diffuse, m.diffuse, 1e-5) << i;  // mirroring rounds E by an ulp
    ASSERT_NEAR(a.specular, m.specular, 1e-5) << i;
  }
}

// A zero tangent is answered from the sphere table over the phase angle. Its
// entries have 64 samples (max error ~0.02 as above) and linear interpolation
// over 3.8 deg adds < 1e-3 on this smooth law, so 0.03 holds; the wrong law
// (2/3) cos a is 0.07 away at 60 deg and more beyond.
TEST(FiberTable, ZeroTangentIsTheLambertSphere) {
  const FiberTable& table = default_table();
  for (double deg = 0.0; deg <= 180.0; deg += 7.5) {
    const double a = deg * kPi / 180.0;
    const FiberResponse r = table.eval(V3f(0.0f), polar(0.3, 1.0), polar(0.3 + a, 1.0));
    EXPECT_NEAR(r.diffuse, sphere_diffuse_exact(std::min(a, kPi)), 0.03) << deg;
  }
}

TEST(FiberTable, DegenerateInputsGiveFiniteResponsesInRange) {
  const FiberTable& table = default_table();
  const V3f t(0, 0, 1), x(1, 0, 0), y(0, 1, 0);
  const V3f vectors[] = {
      t, -t, x, -x, y, V3f(0.0f), V3f(1, 0, -1), V3f(1e-30f, 0, 0), V3f(1e30f, 0, 1e30f)};
  for (const V3f& tangent : vectors) {
    for (const V3f& light : vectors) {
      for (const V3f& eye : vectors) {
        const FiberResponse r = table.eval(tangent, light, eye);
        ASSERT_TRUE(std::isfinite(r.diffuse) && std::isfinite(r.specular));
        ASSERT_GE(r.diffuse, 0.0f);
        ASSERT_LE(r.diffuse, 1.0f);
        ASSERT_GE(r.specular, 0.0f);
        ASSERT_LE(r.specular, 1.0f);
        if (light == V3f(0.0f) || eye == V3f(0.0f)) {
          ASSERT_EQ(r.diffuse, 0.0f);
          ASSERT_EQ(r.specular, 0.0f);
        }
      }
    }
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const FiberResponse r = table.eval(t, V3f(nan, 0, 0), y);
  EXPECT_EQ(r.diffuse, 0.0f);
  EXPECT_EQ(r.specular, 0.0f);
}

// The angles reported for a configuration, exactly (libm) computed.
TEST(FiberAngles, HandComputedConfigurations) {
  const FiberAngles a = fiber_angles(V3f(0, 0, 2), polar(kPi / 3, 0.2), polar(kPi / 4, 0.2 + 1.0));
  EXPECT_NEAR(a.theta_light, kPi / 3, 1e-6);
  EXPECT_NEAR(a.theta_eye, kPi / 4, 1e-6);
  EXPECT_NEAR(a.phi_d, 1.0, 1e-6);
  const FiberAngles b = fiber_angles(V3f(0, 0, 1), V3f(0, 0, 1), V3f(1, 0, 0));
  EXPECT_NEAR(b.theta_light, 0.0, 1e-6);
  EXPECT_EQ(b.phi_d, 0.0f);  // azimuth undefined along the axis
  const FiberAngles c = fiber_angles(V3f(0, 0, 1), V3f(1, 0, 0), V3f(-1, 0, -1));
  EXPECT_NEAR(c.theta_eye, 3 * kPi / 4, 1e-6);
  EXPECT_NEAR(c.phi_d, kPi, 1e-6);
}

TEST(FiberTable, RejectsTooFewBins) {
  FiberTableParams params;
  params.theta_bins = 1;
  EXPECT_THROW(FiberTable::build(params), InputError);
  params.theta_bins = 4;
  params.phi_bins = 0;
  EXPECT_THROW(FiberTable::build(params), InputError);
}

TEST(FiberTable, UnbuiltTableAnswersZero) {
  const FiberResponse r = FiberTable().eval(V3f(0, 0, 1), V3f(1, 0, 0), V3f(0, 1, 0));
  EXPECT_EQ(r.diffuse, 0.0f);
  EXPECT_EQ(r.specular, 0.0f);
}

}  // namespace
}  // namespace clothbake
