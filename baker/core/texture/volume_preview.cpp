#include "core/texture/volume_preview.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/fiber/fiber_model.h"

namespace clothbake {

namespace {
using Imath::V3f;

// Optical depth of the whole cloth thickness at rho = 1 for the top view:
// high enough that a full yarn is opaque, low enough that gaps show.
constexpr float k_preview_optical_depth = 12.0f;

int cell_index(float coord_mm, float cell_mm) { return int(std::floor(coord_mm / cell_mm)); }
}  // namespace

Image preview_top(const VolumeTexture& volume, int repeats, int pixels_per_repeat) {
  const int w = repeats * pixels_per_repeat;
  Image image(w, w, 3);
  const V3f cell = volume.cell_size_mm();
  const V3f to_light_texture = V3f(-0.45f, 0.55f, 0.70f).normalized();
  const V3f to_eye_texture(0.0f, 0.0f, 1.0f);
  const float layer_tau = k_preview_optical_depth / volume.nz();
  tbb::parallel_for(0, w, [&](int py) {
    for (int px = 0; px < w; ++px) {
      // Image y grows downward; texture y grows upward (top of image = +y).
      const float x_mm = (px + 0.5f) / pixels_per_repeat * volume.size_mm().x;
      const float y_mm = (w - py - 0.5f) / pixels_per_repeat * volume.size_mm().y;
      const int i = cell_index(x_mm, cell.x), j = cell_index(y_mm, cell.y);
      V3f radiance(0.0f);
      float transmittance = 1.0f;
      for (int k = volume.nz() - 1; k >= 0 && transmittance > 1e-3f; --k) {
        const Cell& c = volume.at(i, j, k);
        if (c.density <= 0.0f) continue;
        const float alpha = 1.0f - std::exp(-layer_tau * c.density);
        const FiberResponse f = kajiya_kay_fiber(c.tangent, to_light_texture, to_eye_texture,
                                                 std::max(c.exponent, 1.0f));
        const V3f shade = c.diffuse * (0.2f + 0.8f * f.diffuse) + V3f(c.specular * f.specular);
        radiance += shade * (transmittance * alpha);
        transmittance *= 1.0f - alpha;
      }
      radiance += V3f(0.04f) * transmittance;  // dark background through gaps
      std::copy(&radiance.x, &radiance.x + 3, image.at(px, py));
    }
  });
  return image;
}

namespace {
Image section(const VolumeTexture& volume, bool along_warp, float fixed_mm, int repeats,
              float pixels_per_mm) {
  const V3f size = volume.size_mm(), cell = volume.cell_size_mm();
  const float length_mm = (along_warp ? size.y : size.x) * repeats;
  const int w = std::max(1, int(std::lround(length_mm * pixels_per_mm)));
  const int h = std::max(1, int(std::lround(size.z * pixels_per_mm)));
  Image image(w, h, 3);
  const int fixed = along_warp ? cell_index(fixed_mm, cell.x) : cell_index(fixed_mm, cell.y);
  for (int py = 0; py < h; ++py) {
    const float z_mm = size.z * (1.0f - (py + 0.5f) / h);
    const int k = std::clamp(cell_index(z_mm, cell.z), 0, volume.nz() - 1);
    for (int px = 0; px < w; ++px) {
      const float s_mm = (px + 0.5f) / pixels_per_mm;
      const Cell& c = along_warp ? volume.at(fixed, cell_index(s_mm, cell.y), k)
                                 : volume.at(cell_index(s_mm, cell.x), fixed, k);
      const V3f colour = c.diffuse * c.density;
      std::copy(&colour.x, &colour.x + 3, image.at(px, py));
    }
  }
  return image;
}
}  // namespace

Image preview_section_along_warp(const VolumeTexture& volume, float x_mm, int repeats,
                                 float pixels_per_mm) {
  return section(volume, true, x_mm, repeats, pixels_per_mm);
}

Image preview_section_along_weft(const VolumeTexture& volume, float y_mm, int repeats,
                                 float pixels_per_mm) {
  return section(volume, false, y_mm, repeats, pixels_per_mm);
}

Image preview_tangents(const VolumeTexture& volume, int repeats, int pixels_per_repeat) {
  const int w = repeats * pixels_per_repeat;
  Image image(w, w, 3);
  const V3f cell = volume.cell_size_mm();
  for (int py = 0; py < w; ++py)
    for (int px = 0; px < w; ++px) {
      const int i = cell_index((px + 0.5f) / pixels_per_repeat * volume.size_mm().x, cell.x);
      const int j = cell_index((w - py - 0.5f) / pixels_per_repeat * volume.size_mm().y, cell.y);
      V3f colour(0.0f);
      for (int k = volume.nz() - 1; k >= 0; --k) {
        const Cell& c = volume.at(i, j, k);
        if (c.density > 0.05f) {
          colour = V3f(0.5f) + c.tangent * 0.5f;
          break;
        }
      }
      std::copy(&colour.x, &colour.x + 3, image.at(px, py));
    }
  return image;
}

}  // namespace clothbake
