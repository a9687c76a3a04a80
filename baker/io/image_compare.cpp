#include "io/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "core/util/error.h"
#include "io/image_io.h"

namespace clothbake::io {

namespace {
namespace oiio = OIIO;

oiio::ImageBuf rgb_buf(const Image& image) {
  const Image rgb = image.rgb();
  oiio::ImageBuf buf(oiio::ImageSpec(rgb.width, rgb.height, 3, oiio::TypeDesc::FLOAT));
  buf.set_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, rgb.pixels.data());
  return buf;
}
}  // namespace

Image read_image(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError("", "cannot open image (missing)", path);
  oiio::ImageBuf buf(path);
  if (!buf.read(0, 0, true, oiio::TypeDesc::FLOAT))
    throw InputError("", "cannot read image: " + buf.geterror(), path);
  const oiio::ImageSpec& spec = buf.spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!buf.get_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, image.pixels.data()))
    throw InputError("", "cannot read pixels: " + buf.geterror(), path);
  return image;
}

Image downsample(const Image& image, int factor) {
  if (factor <= 1) return image;
  if (image.width % factor || image.height % factor)
    throw InputError("--downsample", std::to_string(image.width) + " x " +
                                         std::to_string(image.height) + " does not divide by " +
                                         std::to_string(factor));
  oiio::ImageBuf src(
      oiio::ImageSpec(image.width, image.height, image.channels, oiio::TypeDesc::FLOAT));
  src.set_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, image.pixels.data());
  const int w = image.width / factor, h = image.height / factor;
  // OpenImageIO sizes the box to one output pixel: the mean of each block.
  oiio::ImageBuf dst =
      oiio::ImageBufAlgo::resize(src, "box", 0.0f, oiio::ROI(0, w, 0, h, 0, 1, 0, image.channels));
  Image out(w, h, image.channels);
  dst.get_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, out.pixels.data());
  return out;
}

ImageDiff compare_images(const Image& reference, const Image& test, double threshold) {
  if (reference.width != test.width || reference.height != test.height)
    throw InputError("", "images differ in size: " + std::to_string(reference.width) + " x " +
                             std::to_string(reference.height) + " against " +
                             std::to_string(test.width) + " x " + std::to_string(test.height));
  const oiio::ImageBuf ref = rgb_buf(reference), tst = rgb_buf(test);
  const oiio::ImageBufAlgo::PixelStats stats = oiio::ImageBufAlgo::computePixelStats(ref);
  ImageDiff d;
  d.width = reference.width;
  d.height = reference.height;
  d.reference_peak = std::max({stats.max[0], stats.max[1], stats.max[2]});
  d.reference_mean = (stats.avg[0] + stats.avg[1] + stats.avg[2]) / 3.0;
  d.threshold = threshold > 0.0 ? threshold : 0.01 * d.reference_peak;
  const auto cmp = oiio::ImageBufAlgo::compare(tst, ref, float(d.threshold), float(d.threshold));
  d.rmse = cmp.rms_error;
  d.max_error = cmp.maxerror;
  d.share_over = double(cmp.nfail) / double(size_t(d.width) * d.height);
  d.relative_rmse = d.reference_mean > 0.0 ? d.rmse / d.reference_mean : 0.0;
  d.psnr_db = d.rmse > 0.0 ? 20.0 * std::log10(d.reference_peak / d.rmse) : INFINITY;
  return d;
}

Image error_heatmap(const Image& reference, const Image& test, double scale_max) {
  Image err(reference.width, reference.height, 1);
  double largest = 0.0;
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) {
      float e = 0.0f;
      for (int c = 0; c < 3; ++c)
        e = std::max(e, std::fabs(test.at(x, y)[c] - reference.at(x, y)[c]));
      err.at(x, y)[0] = e;
      largest = std::max(largest, double(e));
    }
  const double top = scale_max > 0.0 ? scale_max : (largest > 0.0 ? largest : 1.0);
  return color_map(err, "inferno", 0.0f, float(top));
}

Image comparison_sheet(const Image& reference, const Image& test,
                       const std::string& reference_label, const std::string& test_label,
                       const ImageDiff& d) {
  const int w = reference.width, h = reference.height, strip = 24;
  // Display-referred panels: both renders through the sRGB curve, the heat
  // map as it is.
  auto srgb = [](const Image& img) {
    oiio::ImageBuf buf = rgb_buf(img);
    buf = oiio::ImageBufAlgo::colorconvert(buf, "linear", "sRGB");
    Image out(img.width, img.height, 3);
    buf.get_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, out.pixels.data());
    return out;
  };
  const Image panels[3] = {srgb(reference), srgb(test), error_heatmap(reference, test)};
  Image sheet(3 * w, h + strip, 3);
  for (int p = 0; p < 3; ++p)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) sheet.at(p * w + x, y + strip)[c] = panels[p].at(x, y)[c];
  char stats[160];
  std::snprintf(stats, sizeof stats, "|difference|: PSNR %.2f dB, rel. RMSE %.1f%%", d.psnr_db,
                100.0 * d.relative_rmse);
  draw_label(sheet, 6, 17, reference_label, 14);
  draw_label(sheet, w + 6, 17, test_label, 14);
  draw_label(sheet, 2 * w + 6, 17, stats, 14);
  return sheet;
}

}  // namespace clothbake::io
