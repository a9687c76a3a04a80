#include "core/texture/volume_generator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/util/error.h"
#include "core/weave/weave.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr uint64_t k_budget = uint64_t(1) << 32;
constexpr double k_deg = 180.0 / std::numbers::pi;

ClothSpec small_spec() {
  ClothSpec s;
  s.resolution = {32, 32, 12, 2};
  return s;
}

TEST(VolumeGenerator, SameSpecSameBytesForAnyThreadCount) {
  const ClothSpec spec = small_spec();
  uint64_t h1, h2, h3;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    h1 = generate_volume(spec, k_budget).content_hash();
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    h2 = generate_volume(spec, k_budget).content_hash();
    h3 = generate_volume(spec, k_budget).content_hash();
  }
  EXPECT_EQ(h1, h2);
  EXPECT_EQ(h2, h3);
  ClothSpec other = spec;
  other.seed = 2;
  EXPECT_NE(generate_volume(other, k_budget).content_hash(), h1);
}

TEST(VolumeGenerator, CellsAreWellFormed) {
  const VolumeTexture v = generate_volume(small_spec(), k_budget);
  size_t occupied = 0;
  for (const Cell& c : v.cells()) {
    ASSERT_GE(c.density, 0.0f);
    ASSERT_LE(c.density, 1.0f);
    if (c.density > 0.0f) {
      ++occupied;
      EXPECT_NEAR(c.tangent.length(), 1.0f, 1e-5f);
      EXPECT_NE(c.family, YarnFamily::None);
      for (int a = 0; a < 3; ++a) EXPECT_TRUE(c.diffuse[a] >= 0.0f && c.diffuse[a] <= 1.0f);
      EXPECT_TRUE(c.specular >= 0.0f && c.specular <= 1.0f);
      EXPECT_GT(c.exponent, 0.0f);
    } else {
      EXPECT_EQ(c.tangent, V3f(0.0f));
      EXPECT_EQ(c.family, YarnFamily::None);
    }
  }
  // A plain weave of touching yarns is neither empty nor solid.
  EXPECT_GT(occupied, v.cell_count() / 4);
  EXPECT_LT(occupied, v.cell_count());
}

// The family of the top-most occupied cell above each crossing's centre must be
// the yarn the draft puts on top there, for every crossing of several weaves.
TEST(VolumeGenerator, TopYarnFollowsTheDraftAtEveryCrossing) {
  for (const char* pattern :
       {"plain", "twill_2_1", "twill_2_2", "satin_5", "satin_8", "basket_2x2"}) {
    ClothSpec s;
    s.pattern = pattern;
    const WeaveDraft d = WeaveDraft::named(pattern);
    s.resolution = {8 * d.ends(), 8 * d.picks(), 12, 1};
    const VolumeTexture v = generate_volume(s, k_budget);
    for (int p = 0; p < d.picks(); ++p)
      for (int e = 0; e < d.ends(); ++e) {
        const int i = 8 * e + 4, j = 8 * p + 4;  // the cell at the crossing's centre
        YarnFamily top = YarnFamily::None;
        for (int k = v.nz() - 1; k >= 0 && top == YarnFamily::None; --k) top = v.at(i, j, k).family;
        EXPECT_EQ(top, d.warp_up(p, e) ? YarnFamily::Warp : YarnFamily::Weft)
            << pattern << " pick " << p << " end " << e;
      }
  }
}

// Without crimp, yarn axes are exactly +y (warp) and +x (weft); with no random
// spread every fibre then lies at exactly +twist or -twist to its axis, turned
// about the radial direction, and both bundles are present in both families.
TEST(VolumeGenerator, FibresLieAtPlusOrMinusTheTwistAngle) {
  ClothSpec s = small_spec();
  s.crimp = 0.0f;
  s.angle_spread_deg = 0.0f;
  s.resolution.supersample = 1;  // the cell centre decides the yarn
  s.warp.twist_deg = 30.0f;
  s.weft.twist_deg = 20.0f;
  const VolumeTexture v = generate_volume(s, k_budget);
  const V3f cell = v.cell_size_mm();
  const float z_mid = 0.5f * v.size_mm().z;
  int plus[3] = {0, 0, 0}, minus[3] = {0, 0, 0};
  for (int k = 0; k < v.nz(); ++k)
    for (int j = 0; j < v.ny(); ++j)
      for (int i = 0; i < v.nx(); ++i) {
        const Cell& c = v.at(i, j, k);
        if (c.density <= 0.0f) continue;
        const bool warp = c.family == YarnFamily::Warp;
        const V3f axis = warp ? V3f(0, 1, 0) : V3f(1, 0, 0);
        const double twist = warp ? 30.0 : 20.0;
        const double angle = std::acos(std::clamp(double(c.tangent.dot(axis)), -1.0, 1.0)) * k_deg;
        ASSERT_NEAR(angle, twist, 0.01) << i << "," << j << "," << k;
        const V3f p((i + 0.5f) * cell.x, (j + 0.5f) * cell.y, (k + 0.5f) * cell.z);
        const float centre = (std::floor((warp ? p.x : p.y) / 0.5f) + 0.5f) * 0.5f;
        const V3f radial =
            warp ? V3f(p.x - centre, 0, p.z - z_mid) : V3f(0, p.y - centre, p.z - z_mid);
        const V3f off_axis = c.tangent - axis * c.tangent.dot(axis);
        (off_axis.dot(radial.cross(axis)) > 0 ? plus : minus)[int(c.family)]++;
      }
  for (int f = 1; f <= 2; ++f) {
    EXPECT_GT(plus[f], (plus[f] + minus[f]) / 5) << "family " << f;
    EXPECT_GT(minus[f], (plus[f] + minus[f]) / 5) << "family " << f;
  }
}

// The random rotation's angle is |N(0, sigma)|, so its mean square over n cells
// estimates sigma^2 with relative standard deviation sqrt(2/n).
TEST(VolumeGenerator, AngleSpreadHasTheRequestedDeviation) {
  ClothSpec s = small_spec();
  s.crimp = 0.0f;
  s.angle_spread_deg = 5.0f;
  s.warp.twist_deg = s.weft.twist_deg = 30.0f;
  const VolumeTexture v = generate_volume(s, k_budget);
  double sum_sq = 0.0;
  size_t n = 0;
  for (const Cell& c : v.cells()) {
    if (c.density <= 0.0f) continue;
    const V3f axis = c.family == YarnFamily::Warp ? V3f(0, 1, 0) : V3f(1, 0, 0);
    // Deviation from the nearer of the two bundles' exact directions is
    // bounded below by the deviation of the angle to the axis.
    const double angle =
        std::acos(std::clamp(double(std::fabs(c.tangent.dot(axis))), 0.0, 1.0)) * k_deg;
    const double off = angle - 30.0;
    sum_sq += off * off;
    ++n;
  }
  // Rotation by theta ~ N(0, sigma) toward a uniform azimuth psi changes the
  // angle to the axis by ~theta cos(psi) (small angles): E[off^2] = sigma^2 / 2.
  // Per cell, Var(theta^2 cos^2 psi) = 3 sigma^4 * 3/8 - sigma^4 / 4 = 7/8 sigma^4,
  // a relative s.d. of sqrt(7/8) / (1/2) = 1.87; of the mean over n cells,
  // 1.87 / sqrt(n). Allow 5 of those plus 3% for the small-angle approximation.
  const double expected = 5.0 * 5.0 / 2.0;
  const double rel_sd = 1.87 / std::sqrt(double(n));
  EXPECT_NEAR(sum_sq / double(n), expected, expected * (5.0 * rel_sd + 0.03)) << "n = " << n;
}

// With noise off, one sub-sample per cell and no depth factor, rho must equal
// the documented profile edge + (core - edge)(1 - r^2)^p, computed here from
// the yarn geometry independently of the generator.
TEST(VolumeGenerator, DensityFollowsTheDocumentedProfile) {
  ClothSpec s = small_spec();
  s.crimp = 0.0f;
  s.resolution.supersample = 1;
  s.density.noise_amplitude = 0.0f;
  s.density.top_factor = 1.0f;
  s.density.core = 0.9f;
  s.density.edge = 0.3f;
  s.density.falloff = 2.0f;
  const VolumeTexture v = generate_volume(s, k_budget);
  const V3f cell = v.cell_size_mm();
  const float z_mid = 0.5f * v.size_mm().z;
  int checked = 0;
  for (int k = 0; k < v.nz(); ++k)
    for (int j = 0; j < v.ny(); ++j)
      for (int i = 0; i < v.nx(); ++i) {
        const V3f p((i + 0.5f) * cell.x, (j + 0.5f) * cell.y, (k + 0.5f) * cell.z);
        float best = 2.0f;
        for (int e = -1; e <= 2; ++e) {  // warp ends, crimp 0: centre line at z_mid
          const float ex = (p.x - (e + 0.5f) * 0.5f) / 0.22f, ez = (p.z - z_mid) / 0.09f;
          best = std::min(best, ex * ex + ez * ez);
        }
        for (int r = -1; r <= 2; ++r) {
          const float ey = (p.y - (r + 0.5f) * 0.5f) / 0.22f, ez = (p.z - z_mid) / 0.09f;
          best = std::min(best, ey * ey + ez * ez);
        }
        const float expected = best <= 1.0f ? 0.3f + 0.6f * std::pow(1.0f - best, 2.0f) : 0.0f;
        ASSERT_NEAR(v.at(i, j, k).density, expected, 1e-5f) << i << "," << j << "," << k;
        checked += expected > 0.0f;
      }
  EXPECT_GT(checked, 100);
}

// Denser deep in the cloth: with top_factor f, each cell's rho is scaled by
// 1 + (f - 1) smoothstep(height), exactly, when nothing clamps.
TEST(VolumeGenerator, DepthFactorMakesTheSurfaceSparser) {
  ClothSpec s = small_spec();
  s.resolution.supersample = 1;
  s.density.noise_amplitude = 0.0f;
  s.density.top_factor = 1.0f;
  const VolumeTexture a = generate_volume(s, k_budget);
  s.density.top_factor = 0.5f;
  const VolumeTexture b = generate_volume(s, k_budget);
  double top_ratio = 0.0, bottom_ratio = 0.0;
  for (int k = 0; k < a.nz(); ++k) {
    const float h = (k + 0.5f) / a.nz();
    const float smooth = h * h * (3.0f - 2.0f * h);
    const float factor = 1.0f + (0.5f - 1.0f) * smooth;
    for (int j = 0; j < a.ny(); ++j)
      for (int i = 0; i < a.nx(); ++i)
        if (a.at(i, j, k).density > 0.0f)
          ASSERT_NEAR(b.at(i, j, k).density, a.at(i, j, k).density * factor, 1e-5f);
    if (k == a.nz() - 1) top_ratio = factor;
    if (k == 0) bottom_ratio = factor;
  }
  EXPECT_LT(top_ratio, bottom_ratio);
}

// Specular strength grows toward the top, diffuse toward the bottom.
TEST(VolumeGenerator, ShadingIsMoreSpecularOnTopAndMoreDiffuseBelow) {
  const VolumeTexture v = generate_volume(small_spec(), k_budget);
  auto layer_means = [&](int k, double& spec, double& diff) {
    spec = diff = 0.0;
    int n = 0;
    for (int j = 0; j < v.ny(); ++j)
      for (int i = 0; i < v.nx(); ++i) {
        const Cell& c = v.at(i, j, k);
        if (c.density <= 0.0f) continue;
        spec += c.specular;
        diff += (c.diffuse.x + c.diffuse.y + c.diffuse.z) / 3.0;
        ++n;
      }
    spec /= n;
    diff /= n;
  };
  double spec_top, diff_top, spec_bottom, diff_bottom;
  layer_means(v.nz() - 2, spec_top, diff_top);
  layer_means(1, spec_bottom, diff_bottom);
  EXPECT_GT(spec_top, 2.0 * spec_bottom);
  EXPECT_LT(diff_top, diff_bottom);
}

// Periodic in x and y: the jump across the wrap is no larger than the jumps
// between neighbouring cells inside the repeat.
TEST(VolumeGenerator, TexturePeriodicAcrossTheRepeat) {
  const VolumeTexture v = generate_volume(small_spec(), k_budget);
  auto column_diff = [&](int i0, int i1) {
    double d = 0.0;
    for (int k = 0; k < v.nz(); ++k)
      for (int j = 0; j < v.ny(); ++j)
        d += std::fabs(v.at(i0, j, k).density - v.at(i1, j, k).density);
    return d;
  };
  auto row_diff = [&](int j0, int j1) {
    double d = 0.0;
    for (int k = 0; k < v.nz(); ++k)
      for (int i = 0; i < v.nx(); ++i)
        d += std::fabs(v.at(i, j0, k).density - v.at(i, j1, k).density);
    return d;
  };
  double interior_x = 0.0, interior_y = 0.0;
  for (int i = 0; i + 1 < v.nx(); ++i) interior_x = std::max(interior_x, column_diff(i, i + 1));
  for (int j = 0; j + 1 < v.ny(); ++j) interior_y = std::max(interior_y, row_diff(j, j + 1));
  EXPECT_LE(column_diff(v.nx() - 1, 0), interior_x);
  EXPECT_LE(row_diff(v.ny() - 1, 0), interior_y);
}

TEST(VolumeGenerator, RefusesAGridOverTheMemoryBudgetBeforeAllocating) {
  ClothSpec s;
  s.resolution = {100000, 100000, 1000, 1};  // 1e13 cells: would need ~370 TiB
  try {
    (void)generate_volume(s, k_budget);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "resolution");
    EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos) << e.what();
  }
  EXPECT_GT(estimated_volume_bytes(s), uint64_t(1e13) * 36);
}

TEST(VolumeGenerator, BadSpecsNameTheField) {
  auto field_of = [](const ClothSpec& s) -> std::string {
    try {
      (void)generate_volume(s, k_budget);
    } catch (const InputError& e) {
      return e.field();
    }
    return "(no error)";
  };
  ClothSpec s = small_spec();
  s.warp.width_mm = -1.0f;
  EXPECT_EQ(field_of(s), "warp.width_mm");
  s = small_spec();
  s.weft.spacing_mm = 0.0f;
  EXPECT_EQ(field_of(s), "weft.spacing_mm");
  s = small_spec();
  s.resolution.layers = 0;
  EXPECT_EQ(field_of(s), "resolution.layers");
  s = small_spec();
  s.density.edge = 2.0f;
  EXPECT_EQ(field_of(s), "density.edge");
  s = small_spec();
  s.pattern = "tartan";
  EXPECT_EQ(field_of(s), "weave.pattern");
  s = small_spec();
  s.shading.exponent = std::nanf("");
  EXPECT_EQ(field_of(s), "shading.exponent");
}

}  // namespace
}  // namespace clothbake
