#pragma once
/// Writes a volume texture as an OpenVDB file.
///
/// Grids: `density` (float), `tangent` (vec3s), `diffuse` (vec3s), `specular`
/// (float), `exponent` (float). Every cell of the repeat is written as an
/// active leaf voxel, zero or not and never pruned to tiles, because Blender
/// 3.4 renders constant tiles as empty. World units are millimetres of texture
/// space; voxel (i, j, k) is centred at the cell centre ((i+.5)dx, (j+.5)dy,
/// (k+.5)dz), the OpenVDB convention (index i at its voxel's centre).

#include <string>

#include "core/texture/volume_texture.h"

namespace clothbake::io {

/// Names of the grids written, in order.
inline constexpr const char* k_vdb_grid_names[] = {"density", "tangent", "diffuse", "specular",
                                                   "exponent"};

/// Writes `volume` atomically to `path` (temporary file, then rename).
void write_volume_vdb(const std::string& path, const VolumeTexture& volume,
                      const std::string& description);

/// Writes `volume` to `temp` as it is, for a caller that renames it into
/// place itself (write_all_atomically); errors name `path`, the final name.
void write_volume_vdb_to(const std::string& temp, const std::string& path,
                         const VolumeTexture& volume, const std::string& description);

}  // namespace clothbake::io
