#pragma once
/// Reads a volume texture from an OpenVDB file: the reverse of vdb_writer.h,
/// for a texture edited elsewhere (Houdini, a script) or a generated one
/// re-used (`"volume"` of a scene object, docs/formats/scene.md).
///
/// What is accepted (docs/formats/cloth-spec.md, "Reading a VDB back"):
/// - the five grids of k_vdb_grid_names with their value types: `density`
///   float, `tangent` vec3s, `diffuse` vec3s, `specular` float, `exponent`
///   float (other grids are ignored);
/// - one transform shared by all five: linear (the same voxel size
///   everywhere; frustum maps are refused), axis-aligned, positive scale.
///   The voxel size may differ per axis (clothbake's cells usually do);
/// - one active bounding box shared by all five, non-empty. It becomes the
///   texture: its minimum voxel is cell (0, 0, 0); the transform's offset is
///   ignored. Voxels inside the box that are inactive read as the grid's
///   background value;
/// - finite values; density in [0, 1]; diffuse, specular and exponent >= 0;
///   where density > 0 a tangent of length within k_vdb_tangent_tolerance of
///   1 (normalised on reading unless already unit to float precision).
///
/// Texture space: x, y, z of index space scaled by the voxel size, in
/// millimetres. The repeat's size is nx dx x ny dy x nz dz, or the file's
/// `clothbake_size_mm` metadata when that agrees (to 1e-5, relative): the
/// exact floats `clothbake volume` wrote, so a round trip renders the same
/// bytes. Cells read back have YarnFamily::None (the VDB does not store it).

#include <cstdint>
#include <string>

#include "core/texture/volume_texture.h"

namespace clothbake::io {

/// A tangent where density > 0 is accepted if | |v| - 1 | <= this.
inline constexpr float k_vdb_tangent_tolerance = 0.01f;

/// Bytes a dense texture of `cell_count` cells needs while being read: the
/// cells plus the five grids' values (the estimate checked against the budget).
uint64_t estimated_vdb_read_bytes(uint64_t cell_count);

/// Reads and validates `path`. The dense texture's size is estimated from
/// the grids' metadata (written by OpenVDB with the file) before any voxel
/// is read and refused over `memory_budget_bytes`. Throws InputError whose
/// file is `path` and whose field is the offending grid ("density", ...),
/// empty for errors of the file as a whole.
VolumeTexture read_volume_vdb(const std::string& path, uint64_t memory_budget_bytes);

}  // namespace clothbake::io
