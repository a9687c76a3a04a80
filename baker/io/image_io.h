#pragma once
/// Image files through OpenImageIO. Every write goes to a temporary file in the
/// destination folder and is renamed into place, so a reader never sees half a
/// file and a failed write leaves the previous file untouched.

#include <string>

#include "core/util/image.h"

namespace clothbake::io {

/// Writes an 8-bit PNG. `linear` = true applies the sRGB transfer curve first;
/// false writes the values as they are (already display-referred, e.g. colour maps).
void write_png(const std::string& path, const Image& image, bool linear);

/// The same PNG written to `temp` as it is, for a caller that renames it into
/// place itself (write_all_atomically); errors name `path`, the final name.
void write_png_to(const std::string& temp, const std::string& path, const Image& image,
                  bool linear);

/// Writes a float EXR (linear, no transfer curve), channels R,G,B[,A].
void write_exr(const std::string& path, const Image& image);

/// The same EXR written to `temp` as it is, for write_all_atomically.
void write_exr_to(const std::string& temp, const std::string& path, const Image& image);

/// A render's outputs together: the float EXR and, when `png_path` is not
/// empty, its sRGB PNG preview (of the RGB channels). Both appear or neither:
/// a failed write leaves every previous file as it was.
void write_render_images(const std::string& exr_path, const std::string& png_path,
                         const Image& image);

/// Maps a single-channel image through a named OpenImageIO colour map
/// ("inferno", "viridis", "magma", "plasma", "turbo") over [lo, hi] to RGB.
Image color_map(const Image& scalar, const char* map_name, float lo, float hi);

/// Draws text onto an RGB image in place (DejaVu Sans if installed; silently
/// skipped if no font is available, since labels are a convenience).
void draw_label(Image& image, int x, int y, const std::string& text, int font_size, float r = 1.0f,
                float g = 1.0f, float b = 1.0f);

}  // namespace clothbake::io
