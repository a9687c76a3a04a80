#pragma once
/// A plain float image in memory: what the core computes, before the I/O layer
/// turns it into a file. Pixels are row-major, top row first, channels
/// interleaved. Values are linear unless a function says otherwise.

#include <cstddef>
#include <vector>

namespace clothbake {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 3;
  std::vector<float> pixels;  ///< width * height * channels floats

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, 0.0f) {}
  float* at(int x, int y) { return &pixels[(size_t(y) * width + x) * channels]; }
  const float* at(int x, int y) const { return &pixels[(size_t(y) * width + x) * channels]; }

  /// The first three channels (e.g. RGBA -> RGB for a preview).
  Image rgb() const {
    Image out(width, height, 3);
    for (size_t i = 0; i < size_t(width) * height; ++i)
      for (int c = 0; c < 3; ++c)
        out.pixels[i * 3 + c] = c < channels ? pixels[i * channels + c] : 0.0f;
    return out;
  }
};

}  // namespace clothbake
