#pragma once
/// Reads a Weaving Information File (WIF 1.1): the draft (threading with a
/// tie-up and treadling, or a liftplan; rising or sinking shed), every
/// thread's colour and the threads' spacing and thickness. Reading rules and
/// defaults: docs/formats/wif.md. Errors name the file, the section and the line.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/weave/cloth_spec.h"
#include "core/weave/loom_draft.h"

namespace clothbake::io {

/// What a WIF file says about one thread family ([WARP] or [WEFT]). Lengths
/// in mm, colours linear; NaN / -1 where the file says nothing for a thread.
struct WifFamily {
  int threads = 0;
  std::optional<Imath::V3f> color;         ///< [WARP] Color
  std::vector<int> color_index;            ///< [WARP COLORS] per thread, -1 = none; empty = no section
  std::optional<float> spacing_mm;         ///< [WARP] Spacing
  std::optional<float> thickness_mm;       ///< [WARP] Thickness
  std::vector<float> spacings_mm;          ///< [WARP SPACING] per thread; empty = no section
  std::vector<float> thicknesses_mm;       ///< [WARP THICKNESS] per thread; empty = no section
};

struct WifFile {
  LoomDraft loom;
  WifFamily warp, weft;
  std::map<int, Imath::V3f> palette;  ///< [COLOR TABLE], linear
  std::string source_program;         ///< [WIF] Source Program (may be empty)
  std::string path;
};

/// Parses WIF text; `path` is named in errors. Throws InputError with field
/// "[SECTION] line N" (or "[SECTION]" for a missing key).
WifFile parse_wif(const std::string& text, const std::string& path);
WifFile read_wif_file(const std::string& path);

/// True when the path names a WIF file (extension .wif, any case).
bool is_wif_path(const std::string& path);

/// The spec the file describes: its drawdown as the draft, its colours,
/// spacing and thickness (Thickness is the thread's width in the cloth
/// plane; the cross-section's height keeps the default's height-to-width
/// ratio). Everything else keeps `base`'s values.
ClothSpec apply_wif(const WifFile& wif, ClothSpec base);

}  // namespace clothbake::io
