#include "io/image_io.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <utility>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "core/util/error.h"
#include "io/atomic_file.h"

namespace clothbake::io {

namespace {
namespace oiio = OIIO;

oiio::ImageBuf to_imagebuf(const Image& image) {
  oiio::ImageSpec spec(image.width, image.height, image.channels, oiio::TypeDesc::FLOAT);
  oiio::ImageBuf buf(spec);
  buf.set_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, image.pixels.data());
  return buf;
}

/// Writes `buf` to `temp` (a temporary name); errors name `path`, the final one.
void write_buf_to(const std::string& temp, const std::string& path, const oiio::ImageBuf& buf,
                  oiio::TypeDesc type) {
  if (!buf.write(temp, type)) {
    const std::string why = buf.geterror();  // geterror() clears the message
    throw InputError("", "cannot write image: " + (why.empty() ? "write error" : why), path);
  }
}

oiio::ImageBuf png_buf(const Image& image, bool linear) {
  oiio::ImageBuf buf = to_imagebuf(image);
  if (linear) buf = oiio::ImageBufAlgo::colorconvert(buf, "linear", "sRGB");
  return oiio::ImageBufAlgo::clamp(buf, 0.0f, 1.0f);
}

/// A PNG to `temp`. OpenImageIO's PNG writer does not report a failed write
/// (a full disk or a file size limit left an 8 KiB PNG and exit status 0), so
/// the PNG is encoded in memory and written by write_bytes_checked.
void write_png_buf_to(const std::string& temp, const std::string& path, oiio::ImageBuf& buf) {
  OIIO::Filesystem::IOVecOutput memory;
  buf.set_write_ioproxy(&memory);
  const bool ok = buf.write(temp, oiio::TypeDesc::UINT8, "png");
  buf.set_write_ioproxy(nullptr);
  if (!ok) {
    const std::string why = buf.geterror();
    throw InputError("", "cannot write image: " + (why.empty() ? "write error" : why), path);
  }
  write_bytes_checked(temp, path, memory.buffer().data(), memory.buffer().size());
}

oiio::ImageBuf exr_buf(const Image& image) {
  oiio::ImageBuf buf = to_imagebuf(image);
  const char* names4[] = {"R", "G", "B", "A"};
  oiio::ImageSpec& spec = buf.specmod();
  spec.channelnames.clear();
  for (int c = 0; c < image.channels; ++c)
    spec.channelnames.emplace_back(image.channels <= 4 ? names4[c] : "C" + std::to_string(c));
  spec.attribute("compression", "zip");
  // OpenImageIO would stamp the current time: leave it out so equal images
  // give equal bytes.
  spec.attribute("DateTime", "");
  return buf;
}
}  // namespace

void write_png(const std::string& path, const Image& image, bool linear) {
  oiio::ImageBuf buf = png_buf(image, linear);
  write_atomically(path, [&](const std::string& temp) { write_png_buf_to(temp, path, buf); });
}

void write_png_to(const std::string& temp, const std::string& path, const Image& image,
                  bool linear) {
  oiio::ImageBuf buf = png_buf(image, linear);
  write_png_buf_to(temp, path, buf);
}

void write_exr(const std::string& path, const Image& image) {
  const oiio::ImageBuf buf = exr_buf(image);
  write_atomically(
      path, [&](const std::string& temp) { write_buf_to(temp, path, buf, oiio::TypeDesc::FLOAT); });
}

void write_exr_to(const std::string& temp, const std::string& path, const Image& image) {
  write_buf_to(temp, path, exr_buf(image), oiio::TypeDesc::FLOAT);
}

void write_render_images(const std::string& exr_path, const std::string& png_path,
                         const Image& image) {
  const oiio::ImageBuf exr = exr_buf(image);
  std::vector<std::pair<std::string, std::function<void(const std::string&)>>> files;
  files.emplace_back(exr_path, [&](const std::string& temp) {
    write_buf_to(temp, exr_path, exr, oiio::TypeDesc::FLOAT);
  });
  if (!png_path.empty())
    files.emplace_back(png_path, [&](const std::string& temp) {
      oiio::ImageBuf png = png_buf(image.rgb(), true);
      write_png_buf_to(temp, png_path, png);
    });
  write_all_atomically(files);
}

Image color_map(const Image& scalar, const char* map_name, float lo, float hi) {
  Image unit = scalar;
  const float span = hi > lo ? hi - lo : 1.0f;
  for (float& v : unit.pixels) v = std::clamp((v - lo) / span, 0.0f, 1.0f);
  oiio::ImageBuf mapped = oiio::ImageBufAlgo::color_map(to_imagebuf(unit), 0, map_name);
  Image out(scalar.width, scalar.height, 3);
  mapped.get_pixels(oiio::ROI(0, scalar.width, 0, scalar.height, 0, 1, 0, 3), oiio::TypeDesc::FLOAT,
                    out.pixels.data());
  return out;
}

void draw_label(Image& image, int x, int y, const std::string& text, int font_size, float r,
                float g, float b) {
  static const char* k_fonts[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "DejaVuSans"};
  oiio::ImageBuf buf = to_imagebuf(image);
  const float colour[] = {r, g, b, 1.0f};
  for (const char* font : k_fonts) {
    if (!std::filesystem::exists(font) && font[0] == '/') continue;
    if (oiio::ImageBufAlgo::render_text(buf, x, y, text, font_size, font,
                                        oiio::cspan<float>(colour, image.channels))) {
      buf.get_pixels(oiio::ROI::All(), oiio::TypeDesc::FLOAT, image.pixels.data());
      return;
    }
  }
}

}  // namespace clothbake::io
