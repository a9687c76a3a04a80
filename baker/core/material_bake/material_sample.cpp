#include "core/material_bake/material_sample.h"

#include <algorithm>
#include <cmath>

#include "core/march/sample_march.h"
#include "core/util/random.h"

namespace clothbake {

using Imath::V3f;

std::vector<V3f> material_light_directions(const ClothMaterial& material) {
  std::vector<V3f> out(size_t(material.light_count()));
  for (int n = 0; n < material.light_count(); ++n) out[n] = material.light_grid.bake_direction(n);
  return out;
}

LightNodeDirections light_node_directions(const ClothMaterial& material,
                                          std::span<const int> nodes) {
  LightNodeDirections out;
  auto add = [&](int n) {
    const V3f d_material = material.light_grid.bake_direction(n);
    out.local.push_back(material.local_from_material(d_material));
    out.texture.push_back(material.texture_from_material(d_material));
  };
  if (nodes.empty())
    for (int n = 0; n < material.light_count(); ++n) add(n);
  else
    for (int n : nodes) add(n);
  return out;
}

NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const V3f> light_local, int view, int x, int y, int k) {
  return material_sample(material, volume, shader, fields, light_local, view, x, y, k,
                         material.addressed()
                             ? material.crossings.representative[size_t(y / material.texels())]
                             : CrossingClasses::Crossing{});
}

NodeMarchInput material_sample(const ClothMaterial& material, const VolumeTexture& volume,
                               const FiberShader& shader, const LightFieldSet& fields,
                               std::span<const V3f> light_local, int view, int x, int y, int k,
                               const CrossingClasses::Crossing& c) {
  const MaterialSettings& s = material.settings;
  const MaterialOptics& o = material.optics;
  // Addressed per crossing, row y of level 0 lies in block y / R, at a
  // crossing of its class (`c`); its samples are seeded as the texel a
  // whole repeat of R texels per thread would hold there, so that where
  // every crossing is its own class the two bakes march the same samples.
  const uint64_t seed_x = material.addressed() ? uint64_t(c.end) * s.texels + x : uint64_t(x);
  const uint64_t seed_y =
      material.addressed() ? uint64_t(c.pick) * s.texels + uint64_t(y % s.texels) : uint64_t(y);
  Rng rng(hash_key(s.seed, rng_stream::material, uint64_t(view), seed_x, seed_y, uint64_t(k)));
  const V3f size = volume.size_mm();
  float px, py;
  if (material.addressed()) {
    const ThreadSpan sx = thread_span(*material.warp_threads, c.end);
    const ThreadSpan sy = thread_span(*material.weft_threads, c.pick);
    px = sx.left_mm + (float(x) + rng.next_float()) / float(s.texels) * sx.width_mm();
    py = sy.left_mm + (float(y % s.texels) + rng.next_float()) / float(s.texels) * sy.width_mm();
  } else {
    px = (float(x) + rng.next_float()) / float(s.texels) * size.x;
    py = (float(y) + rng.next_float()) / float(s.texels) * size.y;
  }
  const V3f to_eye = material.view_grid.bake_direction(view);
  NodeMarchInput in;
  in.volume = &volume;
  in.shader = &shader;
  in.fields = &fields;
  in.to_light_local = light_local;
  in.to_eye_local = material.local_from_material(to_eye);
  in.depth_scale = o.depth_scale;
  in.sqrt_aspect = std::sqrt(o.aspect);
  in.dir_texture = -material.texture_from_material(to_eye);
  // The entry as ClothScene::shade_surface places it: the top-face point
  // from the front; from behind, the bottom face below it along the ray.
  const SlabEntry slab = slab_entry(volume, V3f(px, py, size.z), in.dir_texture);
  in.entry_texture = slab.entry_texture;
  in.length_mm = slab.length_mm;
  in.extinction_per_mm = o.extinction_per_mm;
  const V3f cell = volume.cell_size_mm();
  in.step_mm = o.step_cells * std::min({cell.x, cell.y, cell.z});
  in.cutoff = o.cutoff;
  in.jitter = rng.next_float();
  in.seed = rng.next_u64();
  in.shading = o.shading;
  in.isotropic_albedo = o.isotropic_albedo;
  in.roulette = o.light_roulette;
  in.colour_parts = material.colour_parts();
  if (in.colour_parts) {
    in.warp_threads = material.warp_threads.get();
    in.weft_threads = material.weft_threads.get();
    in.own_end = in.warp_threads->owner(px);
    in.own_pick = in.weft_threads->owner(py);
  }
  return in;
}

ThreadSpan thread_span(const ThreadLayout& threads, int i) {
  return ThreadSpan{0.5f * (threads.centre_mm(i - 1) + threads.centre_mm(i)),
                    0.5f * (threads.centre_mm(i) + threads.centre_mm(i + 1))};
}

BlockWindow crossing_window(const ClothMaterial& material, const VolumeTexture& volume,
                            const CrossingClasses::Crossing& c) {
  const V3f cell = volume.cell_size_mm();
  const int w = material.settings.context;
  const float x0 = thread_span(*material.warp_threads, c.end - w).left_mm;
  const float x1 = thread_span(*material.warp_threads, c.end + w).right_mm;
  const float y0 = thread_span(*material.weft_threads, c.pick - w).left_mm;
  const float y1 = thread_span(*material.weft_threads, c.pick + w).right_mm;
  BlockWindow b;
  b.x0 = int(std::floor(x0 / cell.x));
  b.y0 = int(std::floor(y0 / cell.y));
  b.cells_x = std::min(volume.nx(), int(std::ceil(x1 / cell.x)) - b.x0);
  b.cells_y = std::min(volume.ny(), int(std::ceil(y1 / cell.y)) - b.y0);
  return b;
}

std::vector<BlockWindow> block_windows(const ClothMaterial& material, const VolumeTexture& volume) {
  std::vector<BlockWindow> out;
  if (!material.addressed()) return out;
  for (const CrossingClasses::Crossing& c : material.crossings.representative)
    out.push_back(crossing_window(material, volume, c));
  return out;
}

}  // namespace clothbake
