#pragma once
/// Data images: EXRs whose named channels hold numbers, not pictures (a
/// lookup's atlases, a material's coefficient levels and light factors).
/// The one place the folder writers and readers talk to OpenImageIO: written
/// zip-compressed with no capture date (the same table gives the same bytes),
/// read back checked against the size and channels the manifest promised,
/// every error naming the file.

#include <string>
#include <vector>

#include <Imath/half.h>

namespace clothbake::io {

/// Writes `width` x `height` pixels of `channels`, interleaved, as halves or
/// floats. `alpha_channel` (or -1) marks the channel readers take as alpha.
void write_data_image(const std::string& path, int width, int height,
                      const std::vector<std::string>& channels, const Imath::half* data,
                      int alpha_channel = -1);
void write_data_image(const std::string& path, int width, int height,
                      const std::vector<std::string>& channels, const float* data,
                      int alpha_channel = -1);

/// What a reader expects of a data image, and how its errors read.
struct DataImageExpect {
  int width = 0, height = 0;
  /// The channels, by name: the file may store them in any order. With
  /// `by_name` false, the file's first channels.size() channels, in order.
  std::vector<std::string> channels;
  bool by_name = true;
  bool finite = false;  ///< refuse a value that is not finite
  std::string missing;  ///< the whole message for a missing file
  std::string cannot_read = "cannot read: ";  ///< before the library's reason
  std::string corrupt = "corrupt or truncated";  ///< the reason when it gives none
  std::string size_from = "the manifest";   ///< "... pixels; <size_from> says W x H"
  std::string channels_from;                ///< "has N channels; <channels_from>"
};

/// Reads an image of exactly the expected size and channels, interleaved.
std::vector<Imath::half> read_data_image_half(const std::string& path, const DataImageExpect& want);
std::vector<float> read_data_image_float(const std::string& path, const DataImageExpect& want);

}  // namespace clothbake::io
