#pragma once
/// The material bake: one weave repeat's appearance for every view node,
/// light node and texel (docs/material-format.md), computed from the volume
/// texture alone (no scene, no lights, no mesh):
///  1. the transmittance toward every light node, one field each over the
///     repeat (light_fields.h);
///  2. per view node, each texel's jittered samples marched once for all
///     light nodes (node_march.h) into a texels x RGB by light-node matrix;
///  3. that matrix factorised (truncated SVD through its Gram matrix) to the
///     smallest rank whose relative error meets `max_error`;
///  4. the mip levels, box averages of level 0.
/// Deterministic for any thread count: every texel sample is seeded by its
/// own indices and each view node is factorised by one thread.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/fiber/fiber_shader.h"
#include "core/material/cloth_material.h"
#include "core/material/material_settings.h"
#include "core/material/node_march.h"
#include "core/texture/volume_texture.h"

namespace clothbake {

/// Throws InputError naming the field for a setting out of range.
void check_material_settings(const MaterialSettings& settings);

struct MaterialBakeStats {
  uint64_t rays = 0;               ///< view marches (texels x spp x view nodes)
  uint64_t march_samples = 0;      ///< view samples shaded
  uint64_t fiber_evaluations = 0;  ///< cells x light nodes
  uint64_t field_bytes = 0;        ///< the light fields
  double uncompressed_values = 0;  ///< texels x views x lights x RGB at level 0, before the SVD
};

/// The span thread i owns across its family (between the midpoints to its
/// neighbours' centres), texture mm, unwrapped like centre_mm.
struct ThreadSpan {
  float left_mm = 0.0f, right_mm = 0.0f;
  float width_mm() const { return right_mm - left_mm; }
};
ThreadSpan thread_span(const ThreadLayout& threads, int i);

/// Addressed per crossing: the cells a block's light fields span, the
/// representative crossing and `context` crossings either side (indices
/// may run below 0 or past the volume: they wrap).
struct BlockWindow {
  int x0 = 0, y0 = 0, cells_x = 0, cells_y = 0;
};
std::vector<BlockWindow> block_windows(const ClothMaterial& material, const VolumeTexture& volume);
/// The window around one crossing.
BlockWindow crossing_window(const ClothMaterial& material, const VolumeTexture& volume,
                            const CrossingClasses::Crossing& c);

/// The light fields the bake holds at once: the whole repeat's, or the
/// largest block window's when addressed.
uint64_t material_field_bytes(const ClothMaterial& material, const VolumeTexture& volume);

/// Bytes the bake holds before the factorised table grows: the light fields
/// (the blocks' windows when addressed) and one view's matrix per thread.
/// `material`: unbaked_material with its cloth set.
uint64_t material_bake_fixed_bytes(const ClothMaterial& material, const VolumeTexture& volume,
                                   int threads);

/// Bakes the material, or part `shard` of it (its view nodes only,
/// material_shard.h). Colour-free parts (settings.parts) need the
/// colour-free cloth `volume` was generated from (its threads decide which
/// parts are a sample's own and which its neighbours'). `memory_budget_bytes` bounds the fields plus the
/// factorised table as it grows (InputError on "memory" when exceeded).
/// `progress(fraction)` is called serialised from workers.
ClothMaterial bake_material(const VolumeTexture& volume, const FiberShader& shader,
                            const MaterialOptics& optics, const MaterialSettings& settings,
                            uint64_t memory_budget_bytes,
                            const std::function<void(double)>& progress = {},
                            MaterialBakeStats* stats = nullptr,
                            const ClothSpec* colour_free_cloth = nullptr,
                            const MaterialShard& shard = {});

/// The march of sample k of texel (x, y) toward view node `view`, exactly as
/// bake_material runs it (its seeds, jitter and entry point); `material`
/// supplies the grids and settings, `light_local` the light nodes' bake
/// directions. For tests: the same march with one light is march_view_ray.
NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const Imath::V3f> light_local, int view, int x, int y,
                               int k);
/// Addressed per crossing: the same at crossing `at` of the block's class
/// (one of its members, settings.members) instead of its representative.
NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const Imath::V3f> light_local, int view, int x, int y,
                               int k, const CrossingClasses::Crossing& at);

/// The light nodes' bake directions in the material's frame.
std::vector<Imath::V3f> material_light_directions(const ClothMaterial& material);

/// Light nodes in the two frames the bake uses them in: local, where the
/// fibres are shaded (ClothMaterial::local_from_material: the world's angles
/// on a stretched map), and texture space, along which their light fields
/// are marched.
struct LightNodeDirections {
  std::vector<Imath::V3f> local;
  std::vector<Imath::V3f> texture;
};
/// The light nodes `nodes` (every node when empty), in that order.
LightNodeDirections light_node_directions(const ClothMaterial& material,
                                          std::span<const int> nodes = {});

/// A material with the settings' grids, the volume's extent and hash, and
/// no table: what bake_material fills.
ClothMaterial unbaked_material(const VolumeTexture& volume, const MaterialOptics& optics,
                               const MaterialSettings& settings);

/// Whether the bake tabulates the fibre response per view node
/// (FiberLightTable) rather than evaluating the model per cell.
bool tabulates_fiber(const MaterialSettings& settings, const MaterialOptics& optics);


}  // namespace clothbake
