#include "io/data_image.h"

#include <cmath>
#include <filesystem>
#include <system_error>

#include <OpenImageIO/imageio.h>

#include "core/util/error.h"

namespace clothbake::io {

namespace {
namespace oiio = OIIO;

void write_typed(const std::string& path, int width, int height,
                 const std::vector<std::string>& channels, oiio::TypeDesc type, const void* data,
                 int alpha_channel) {
  oiio::ImageSpec spec(width, height, int(channels.size()), type);
  spec.channelnames = channels;
  if (alpha_channel >= 0) spec.alpha_channel = alpha_channel;
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");  // no capture date: the same table gives the same bytes
  auto out = oiio::ImageOutput::create(path);
  if (!out) throw InputError("", oiio::geterror(), path);
  if (!out->open(path, spec) || !out->write_image(type, data) || !out->close()) {
    const std::string why = out->geterror();  // geterror() clears the message
    throw InputError("", why.empty() ? "write error" : why, path);
  }
}

template <typename T>
std::vector<T> read_typed(const std::string& path, const DataImageExpect& want,
                          oiio::TypeDesc type) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError("", want.missing, path);
  auto in = oiio::ImageInput::open(path);
  if (!in) throw InputError("", want.cannot_read + oiio::geterror(), path);
  const oiio::ImageSpec& spec = in->spec();
  const size_t nc = want.channels.size();
  if (!want.by_name && spec.nchannels != int(nc))
    throw InputError("", "has " + std::to_string(spec.nchannels) + " channels; " + want.channels_from,
                     path);
  if (spec.width != want.width || spec.height != want.height || spec.depth != 1)
    throw InputError("", "is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                             " pixels; " + want.size_from + " says " + std::to_string(want.width) +
                             " x " + std::to_string(want.height),
                     path);
  if (spec.nchannels != int(nc))
    throw InputError("", "has " + std::to_string(spec.nchannels) + " channels; " + want.channels_from,
                     path);
  std::vector<int> from(nc);
  for (size_t c = 0; c < nc; ++c) {
    from[c] = want.by_name ? -1 : int(c);
    for (int f = 0; want.by_name && f < spec.nchannels; ++f)
      if (spec.channelnames[f] == want.channels[c]) from[c] = f;
    if (from[c] < 0) throw InputError("", "has no channel \"" + want.channels[c] + "\"", path);
  }
  const size_t pixels = size_t(want.width) * size_t(want.height);
  std::vector<T> file(pixels * nc);
  if (!in->read_image(0, 0, 0, spec.nchannels, type, file.data())) {
    const std::string why = in->geterror();
    throw InputError("", want.cannot_read + (why.empty() ? want.corrupt : why), path);
  }
  in->close();
  bool in_order = true;
  for (size_t c = 0; c < nc; ++c) in_order = in_order && from[c] == int(c);
  std::vector<T> data = in_order ? std::move(file) : std::vector<T>(pixels * nc);
  if (!in_order)
    for (size_t p = 0; p < pixels; ++p)
      for (size_t c = 0; c < nc; ++c) data[p * nc + c] = file[p * nc + size_t(from[c])];
  if (want.finite)
    for (const T& x : data)
      if (!std::isfinite(float(x))) throw InputError("", "holds a value that is not finite", path);
  return data;
}
}  // namespace

void write_data_image(const std::string& path, int width, int height,
                      const std::vector<std::string>& channels, const Imath::half* data,
                      int alpha_channel) {
  write_typed(path, width, height, channels, oiio::TypeDesc::HALF, data, alpha_channel);
}

void write_data_image(const std::string& path, int width, int height,
                      const std::vector<std::string>& channels, const float* data,
                      int alpha_channel) {
  write_typed(path, width, height, channels, oiio::TypeDesc::FLOAT, data, alpha_channel);
}

std::vector<Imath::half> read_data_image_half(const std::string& path, const DataImageExpect& want) {
  return read_typed<Imath::half>(path, want, oiio::TypeDesc::HALF);
}

std::vector<float> read_data_image_float(const std::string& path, const DataImageExpect& want) {
  return read_typed<float>(path, want, oiio::TypeDesc::FLOAT);
}

}  // namespace clothbake::io
