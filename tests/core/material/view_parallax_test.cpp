#include "core/material/view_parallax.h"
#include "core/material_bake/parallax_fit.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/material/cloth_material.h"

namespace clothbake {
namespace {

using Imath::V2f;
using Imath::V3f;

// Zero depth or the eye on the node: no shift. Otherwise the two rays meet
// at depth h: x + shift - h slope(node) = x - h slope(eye), in texture mm
// (the material frame's slope over the depth scale).
TEST(ViewParallax, ShiftMakesTheRaysMeetAtTheDepth) {
  const V3f eye = V3f(0.3f, -0.5f, 0.6f).normalized(), node = V3f(0.1f, -0.2f, 0.9f).normalized();
  EXPECT_EQ(parallax_shift_mm(eye, node, 0.0f, 1.0f), V2f(0.0f));
  EXPECT_EQ(parallax_shift_mm(eye, eye, 0.2f, 1.0f), V2f(0.0f));
  for (const float depth_scale : {1.0f, 2.5f}) {
    const float h = 0.2f;
    const V2f shift = parallax_shift_mm(eye, node, h, depth_scale);
    // Texture-space rays: direction (x, y, z * depth_scale).
    const auto at_depth = [&](const V3f& d, V2f x) {
      return x - V2f(d.x, d.y) * (h / (d.z * depth_scale));
    };
    const V2f eye_at = at_depth(eye, V2f(0.0f)), node_at = at_depth(node, shift);
    EXPECT_NEAR(eye_at.x, node_at.x, 1e-6f);
    EXPECT_NEAR(eye_at.y, node_at.y, 1e-6f);
  }
  // At and below the horizon the slope stays finite (the bake's 1-degree clamp).
  const V2f s = material_slope(V3f(1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(s.x, 1.0f / 0.0174524f, 1e-2f);
  EXPECT_EQ(material_slope(V3f(0.0f, 0.6f, -0.8f)), V2f(0.0f, 0.75f));
}

/// A rank-1 material whose every view node shows one pattern P seen through
/// a slab at depth h0: node v's texel x holds P(x - h0 slope(v)), as a ray
/// scattering only at h0 would. Colours grey, light factors 1.
ClothMaterial sheared_material(float h0_mm) {
  ClothMaterial m;
  m.settings.texels = 32;
  m.settings.directions = 6;
  m.settings.light_directions = 2;
  m.repeat_mm = V3f(1.0f, 1.2f, 0.4f);
  m.view_grid.k = m.settings.directions;
  m.light_grid.k = m.settings.light_directions;
  m.max_rank = 1;
  m.allocate();
  m.rank.assign(size_t(m.view_count()), 1);
  std::fill(m.light_factors.begin(), m.light_factors.end(), 1.0f);
  const int side = m.texels();
  constexpr float two_pi = 2.0f * std::numbers::pi_v<float>;
  for (int v = 0; v < m.view_count(); ++v) {
    const V2f slope = material_slope(m.view_grid.node_direction(v));
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {
        const float px = (float(x) + 0.5f) / float(side) * m.repeat_mm.x - h0_mm * slope.x;
        const float py = (float(y) + 0.5f) / float(side) * m.repeat_mm.y - h0_mm * slope.y;
        const float p = 2.0f + std::sin(two_pi * px / m.repeat_mm.x) +
                        0.5f * std::cos(two_pi * 2.0f * py / m.repeat_mm.y);
        m.coefficients[0][size_t(v) * side * side + size_t(y) * side + x] = V3f(p / 3.0f);
        m.alpha[0][size_t(v) * side * side + size_t(y) * side + x] = 1.0f;
      }
  }
  m.build_mips();
  return m;
}

// The fit finds the depth the tables were sheared at (to its step of
// thickness / 80), where neighbours then agree far better than unshifted;
// and for an unsheared material it keeps depth 0.
TEST(ViewParallax, FitRecoversTheShearDepth) {
  const float step = 0.4f / 80.0f;
  for (const float h0 : {0.05f, 0.1f}) {
    const ViewParallaxFit fit = fit_view_parallax(sheared_material(h0));
    EXPECT_NEAR(fit.depth_mm, h0, step * 1.01f) << "h0 " << h0;
    EXPECT_LT(fit.mismatch, 0.05f * fit.mismatch_at_zero) << "h0 " << h0;
  }
  const ViewParallaxFit flat = fit_view_parallax(sheared_material(0.0f));
  EXPECT_EQ(flat.depth_mm, 0.0f);
}

// shade() at the fitted depth: exact on the nodes (the eye on a node reads
// it unshifted) and, between nodes, the sheared pattern's value at the
// eye's own slope, where the unshifted blend is off.
TEST(ViewParallax, ShadeBetweenNodesFollowsTheShear) {
  const float h0 = 0.1f;
  ClothMaterial m = sheared_material(h0);
  const ClothMaterial::Light light{V3f(0.0f, 0.0f, 1.0f), V3f(1.0f)};
  const float x = 0.37f, y = 0.81f;
  const V3f on_node = m.view_grid.node_direction(0, 2, 3);
  const float unshifted_on_node = m.shade(x, y, 1.0f, on_node, {&light, 1}).radiance.x;
  m.parallax_depth_mm = h0;
  EXPECT_FLOAT_EQ(m.shade(x, y, 1.0f, on_node, {&light, 1}).radiance.x, unshifted_on_node);
  // Between nodes, where the slopes of neighbours differ by about 1: RMS
  // over a 7 x 7 grid of points against P at the eye's own slope.
  constexpr float two_pi = 2.0f * std::numbers::pi_v<float>;
  const V3f eye = (m.view_grid.node_direction(0, 4, 2) + m.view_grid.node_direction(0, 3, 3) +
                   m.view_grid.node_direction(0, 4, 3))
                      .normalized();
  const V2f slope = material_slope(eye);
  double err_shifted = 0.0, err_unshifted = 0.0;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      const float px = 0.13f * float(i), py = 0.17f * float(j);
      const float qx = px - h0 * slope.x, qy = py - h0 * slope.y;
      // The light factors are 1: the value is the coefficient itself.
      const float want = (2.0f + std::sin(two_pi * qx / m.repeat_mm.x) +
                          0.5f * std::cos(two_pi * 2.0f * qy / m.repeat_mm.y)) /
                         3.0f;
      m.parallax_depth_mm = h0;
      err_shifted += std::pow(m.shade(px, py, 1.0f, eye, {&light, 1}).radiance.x - want, 2);
      m.parallax_depth_mm = 0.0f;
      err_unshifted += std::pow(m.shade(px, py, 1.0f, eye, {&light, 1}).radiance.x - want, 2);
    }
  EXPECT_LT(std::sqrt(err_shifted / 49), 0.25 * std::sqrt(err_unshifted / 49))
      << "shifted " << std::sqrt(err_shifted / 49) << ", unshifted "
      << std::sqrt(err_unshifted / 49);
}

}  // namespace
}  // namespace clothbake
