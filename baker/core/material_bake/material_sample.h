#pragma once
/// Where a material bake's samples are (material_bake.h): the light nodes'
/// directions, the threads' spans a crossing's texels cover, the cells a
/// block's light fields span, and the march of one texel sample, seeded by
/// its own indices so that any thread count and any shard march it alike.

#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/fiber/fiber_shader.h"
#include "core/material/cloth_material.h"
#include "core/material_bake/light_fields.h"
#include "core/material_bake/node_march.h"
#include "core/texture/volume_texture.h"
#include "core/weave/thread_layout.h"

namespace clothbake {

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

}  // namespace clothbake
