#pragma once
/// A cloth material folder on disk (docs/formats/material.md): manifest.json,
/// one half-float EXR per mip level (the coefficient atlas, alpha first) and
/// light_factors.exr (float). Written into a temporary sibling folder and
/// swapped in whole; read back with every field and image checked against the
/// manifest, errors naming the file and the field.

#include <cstdint>
#include <string>

#include "core/material/cloth_material.h"
#include "core/material_bake/material_bake.h"

namespace clothbake::io {

inline constexpr const char* k_material_format_name = "clothbake-material";
/// 3: addressed per crossing (written only for such a material; the others
/// are written as 2).
inline constexpr int k_material_format_version = 3;

/// What a material folder records besides the table.
struct MaterialInfo {
  std::string cloth_name;  ///< the scene object's name, or the spec file's stem
  std::string source;      ///< the spec or scene file it was baked from
  // The cloth's hash is the material's own (ClothMaterial::cloth_hash).
  MaterialBakeStats stats;
  double seconds = 0.0;  ///< the bake's wall time
  int threads = 0;
};

/// Bytes the folder's images take uncompressed (half coefficients and alpha,
/// float light factors): the bound a disk check uses.
uint64_t material_uncompressed_bytes(const ClothMaterial& material);

/// True when `dir` holds a manifest.json whose format is a material's.
bool is_material_folder(const std::string& dir);

/// Writes the folder atomically; an existing folder is replaced only if it is
/// a material or lookup folder (or empty).
void write_material(const std::string& dir, const ClothMaterial& material,
                    const MaterialInfo& info);

/// Whether a reader takes one part of a sharded bake (material_shard.h):
/// only merge does; anything that renders needs the whole material.
enum class SharedParts { Refuse, Accept };

/// Reads and checks a material folder. A manifest whose table would not fit
/// `memory_budget_bytes` (as floats in memory) is refused before anything
/// is allocated.
ClothMaterial read_material(const std::string& dir, MaterialInfo& info,
                            uint64_t memory_budget_bytes = uint64_t(1) << 40,
                            SharedParts parts = SharedParts::Refuse);

}  // namespace clothbake::io
