#pragma once
/// Comparing two renders of one scene (OpenImageIO's ImageBufAlgo::compare
/// and computePixelStats underneath). All metrics are over the RGB channels.

#include <string>

#include "core/util/image.h"

namespace clothbake::io {

struct ImageDiff {
  double rmse = 0.0;           ///< root mean square error over RGB
  double relative_rmse = 0.0;  ///< rmse / mean of the reference's RGB
  double psnr_db = 0.0;        ///< 20 log10(peak / rmse), peak = the reference's RGB maximum
  double max_error = 0.0;      ///< largest absolute difference of any channel
  double share_over = 0.0;     ///< share of pixels whose largest channel error exceeds `threshold`
  double threshold = 0.0;      ///< the absolute threshold used for share_over
  double reference_mean = 0.0;
  double reference_peak = 0.0;
  int width = 0, height = 0;
};

/// Reads an image file (any OpenImageIO format) as float. Throws InputError
/// naming the file when it is missing or unreadable.
Image read_image(const std::string& path);

/// Box-filters `image` down by an integer `factor` (each output pixel the mean
/// of factor x factor input pixels); sizes must divide.
Image downsample(const Image& image, int factor);

/// `reference` and `test` must have the same size (InputError otherwise).
/// `threshold` <= 0 means 1% of the reference's peak.
ImageDiff compare_images(const Image& reference, const Image& test, double threshold = 0.0);

/// |test - reference| (max over RGB) as an inferno heat map, scaled so that
/// `scale_max` (<= 0: the largest error) is white-hot.
Image error_heatmap(const Image& reference, const Image& test, double scale_max = 0.0);

/// A comparison sheet for people: reference | test | heat map side by side
/// (sRGB previews of the two images), each captioned.
Image comparison_sheet(const Image& reference, const Image& test,
                       const std::string& reference_label, const std::string& test_label,
                       const ImageDiff& diff);

}  // namespace clothbake::io
