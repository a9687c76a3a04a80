// Measures the interpolation error of the two direction maps by elevation,
// the figures behind the choice of the lookup's map (docs/formats/lookup.md,
// "Why hemi-octahedral"), and holds the two facts they show: a function
// of elevation alone (the slab: see-through and path length, steep toward
// grazing) is interpolated better by the polar map in every band, and an
// azimuthal feature near the horizon (a Phong lobe) better by the
// hemi-octahedral map, whose horizon carries 4 (K - 1) nodes to the polar
// map's K.
#include "core/geometry/direction_grid.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/util/random.h"

namespace clothbake {
namespace {

using Imath::V3f;
constexpr double k_pi = std::numbers::pi;

/// Bilinear interpolation of f from the nodes of `g` (front side).
double interpolate(const DirectionGrid& g, const std::function<double(const V3f&)>& f,
                   const V3f& d) {
  const DirectionGrid::Footprint fp = g.locate(d);
  auto node = [&](int i, int j) { return f(g.node_direction(0, i, j)); };
  return (node(fp.i0, fp.j0) * (1 - fp.fx) + node(fp.i1, fp.j0) * fp.fx) * (1 - fp.fy) +
         (node(fp.i0, fp.j1) * (1 - fp.fx) + node(fp.i1, fp.j1) * fp.fx) * fp.fy;
}

/// RMS error of interpolating f, over random directions in elevation band
/// [lo, hi] degrees above the horizon.
double band_error(const DirectionGrid& g, const std::function<double(const V3f&)>& f, double lo,
                  double hi) {
  Rng rng(42);
  double se = 0.0, norm = 0.0;
  for (int n = 0; n < 4000; ++n) {
    const double elev = (lo + (hi - lo) * rng.next_double()) * k_pi / 180.0;
    const double phi = 2.0 * k_pi * rng.next_double();
    const V3f d(float(std::cos(elev) * std::cos(phi)), float(std::cos(elev) * std::sin(phi)),
                float(std::sin(elev)));
    const double e = interpolate(g, f, d) - f(d);
    se += e * e;
    norm += f(d) * f(d);
  }
  return std::sqrt(se / norm);  // relative to the function's RMS in the band
}

TEST(DirectionMaps, ElevationFunctionsFavourPolarAzimuthalLobesFavourHemiOctahedral) {
  // Two test functions: the slab's single scattering (a function of the
  // elevation only, steep toward grazing) and a Phong lobe of exponent 24
  // around a reflection direction 70 degrees from the normal.
  const double mu_l = std::cos(45.0 * k_pi / 180.0), tau0 = 1.8;
  const std::function<double(const V3f&)> slab = [&](const V3f& d) {
    const double mu_v = std::max(double(d.z), 0.0174524);
    return mu_l / (mu_l + mu_v) * (1.0 - std::exp(-tau0 * (1.0 / mu_v + 1.0 / mu_l)));
  };
  const V3f r = V3f(std::sin(1.2217f), 0.0f, std::cos(1.2217f));
  const std::function<double(const V3f&)> lobe = [&](const V3f& d) {
    return std::pow(std::max(0.0, double(d.dot(r))), 24.0);
  };
  const double bands[][2] = {{0, 5}, {5, 15}, {15, 30}, {30, 60}, {60, 90}};
  for (int k : {8, 16}) {
    DirectionGrid polar{k, DirectionMap::Polar}, octa{k, DirectionMap::HemiOctahedral};
    for (const auto& [name, f] : {std::pair{"slab", slab}, std::pair{"lobe", lobe}}) {
      for (const auto& b : bands) {
        const double ep = band_error(polar, f, b[0], b[1]), eo = band_error(octa, f, b[0], b[1]);
        std::printf(
            "K %2d %s elevation %2.0f-%2.0f deg: relative RMS error polar %.4f, hemi-oct %.4f\n", k,
            name, b[0], b[1], ep, eo);
        if (name == std::string("slab")) EXPECT_LT(ep, eo) << "slab K " << k << " band " << b[0];
        if (name == std::string("lobe") && k == 8 && b[1] <= 30.0)
          EXPECT_LT(eo, ep) << "lobe K 8 band " << b[0];
      }
    }
  }
}

}  // namespace
}  // namespace clothbake
