#pragma once
/// A cloth material: the appearance of one weave repeat for every view and
/// light direction, prefiltered for every distance (docs/formats/material.md).
///
/// For view node v, light node n and a texel x of mip level m, radiance per
/// unit irradiance is stored factorised per view node (a truncated SVD of
/// that node's texels x RGB by light-node matrix):
///   L(x, v, n) = sum_k<rank[v] coefficient_m(x, v, k) [RGB] * light_factor(v, n, k),
/// and alpha (1 - see-through) per (x, v). The coefficients are RGB, or the
/// colour-free parts (specular, warp diffuse, weft diffuse) that shade()
/// multiplies by the yarn colours (settings.parts, yarn_colours.h). Level 0 has R x R texels over the
/// repeat's top face, each the average over its footprint; level m + 1 is the
/// exact 2 x 2 box average of level m, down to 1 x 1. Since both the
/// coefficients and alpha are linear in area, a lookup at the footprint's
/// level is exact prefiltering for fixed directions.
///
/// Directions live in the material's frame: texture axes x (weft), y (warp),
/// z (up), with z divided by the depth scale (material_settings.h), so a
/// direction d_texture reads as (d.x, d.y, d.z / depth_scale), normalised.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/geometry/direction_grid.h"
#include "core/march/volume_march.h"
#include "core/material/material_layout.h"
#include "core/material/material_settings.h"
#include "core/material/yarn_colours.h"
#include "core/weave/cloth_spec.h"
#include "core/weave/crossing_neighbourhoods.h"
#include "core/weave/thread_layout.h"

namespace clothbake {

/// Components a lookup handles (the rank of a view node): at most the light
/// nodes, 2 KL^2, KL <= k_max_material_directions (material_settings.h).
inline constexpr int k_max_components = 2 * k_max_material_directions * k_max_material_directions;

class ClothMaterial {
 public:
  MaterialSettings settings;  ///< what the bake was asked (texels, directions, spp, error, seed)
  MaterialOptics optics;      ///< what the appearance depends on besides the volume
  Imath::V3f repeat_mm{1, 1, 1};  ///< the volume texture's extent: x, y repeat, z thickness
  /// The volume texture's content hash (VolumeTexture::content_hash): a
  /// scene's cloth must hash the same to use the material.
  uint64_t cloth_hash = 0;
  /// Colour-free parts only: the colour-free cloth spec baked
  /// (cloth_colours.h), the colours it was baked with and their strips, which
  /// shade() uses when it is given none.
  ClothSpec cloth;
  YarnPalette palette;
  YarnColours colours;
  /// Repeats of `cloth` in one repeat of the baked cloth's draft as written
  /// (colour_free_repeats): what a reader that maps UVs by repeats_per_uv
  /// multiplies by (a WIF written over its colour repeat is baked over its
  /// weave's). 1 x 1 for RGB parts.
  Imath::V2f written_repeats{1.0f, 1.0f};
  std::shared_ptr<const ThreadLayout> warp_threads, weft_threads;  ///< of `cloth`
  /// Addressed per crossing (settings.address): every crossing of `cloth`'s
  /// repeat and its class, the block that holds its texels (set_cloth).
  CrossingClasses crossings;
  DirectionGrid view_grid, light_grid;
  /// A part of a sharded bake holds only its view nodes (material_shard.h);
  /// the others have rank 0 and zero tables until the parts are merged.
  MaterialShard shard;
  int max_rank = 0;            ///< coefficient slots per texel (the largest rank)
  std::vector<int> rank;       ///< per view node
  std::vector<float> error;    ///< per view node: relative RMSE of its factorisation, level 0
  /// Per level m (R >> m texels a side): [(view * texels_m + texel) * max_rank + k] RGB,
  /// or (specular, own warp, own weft) for colour-free parts.
  std::vector<std::vector<Imath::V3f>> coefficients;
  /// Colour-free parts only, indexed as `coefficients`: the warp and weft
  /// diffuse of the threads next to the texel's own, on the side the view
  /// ray runs toward (its view node's), shown in those threads' colours.
  std::vector<std::vector<Imath::V2f>> coefficients_next;
  /// The depth (texture mm) at which shade() aligns neighbouring view nodes
  /// (view_parallax.h); 0: no shift, each node read at the eye's x.
  float parallax_depth_mm = 0.0f;
  /// Per level: [view * texels_m + texel], texel = y * side + x.
  std::vector<std::vector<float>> alpha;
  /// [(view * light_nodes + node) * max_rank + k].
  std::vector<float> light_factors;

  /// The table's shape (material_layout.h), from the settings' R, K and KL.
  MaterialLayout layout() const { return MaterialLayout::of(settings, crossings.count()); }
  bool addressed() const { return settings.address == MaterialAddress::Crossings; }
  int texels() const { return settings.texels; }
  int levels() const { return int(coefficients.size()); }
  int level_side(int level) const { return layout().level_side(level); }
  int view_count() const { return layout().view_count(); }
  int light_count() const { return layout().light_count(); }
  /// Allocates the level arrays for the settings' R, K, KL and max_rank.
  void allocate();
  /// Recomputes levels 1.. from level 0 by 2 x 2 box averages (inside each
  /// block when addressed).
  void build_mips();
  bool colour_parts() const { return settings.parts == MaterialParts::SpecularWarpWeft; }
  /// Sets the colour-free cloth and the colours shade() uses by default.
  void set_cloth(const ClothSpec& colour_free_spec, const YarnPalette& baked_palette);
  /// The strips of `p` on this material's cloth (colour-free parts only).
  YarnColours colours_of(const YarnPalette& p) const;

  /// A texture-space direction in the material's frame (unit).
  Imath::V3f material_from_texture(const Imath::V3f& d_texture) const;
  /// A direction in the material's frame in the local (shading) frame, the
  /// world's true angles at a map of optics.aspect: (d.x * sqrt(aspect),
  /// d.y / sqrt(aspect), d.z), normalised (texture (x, y, z) over
  /// mm_per_world, scaled by sqrt(mm_per_world.x * mm_per_world.y)). The
  /// identity at aspect 1.
  Imath::V3f local_from_material(const Imath::V3f& d_material) const;
  /// The material's frame back to texture space (unit).
  Imath::V3f texture_from_material(const Imath::V3f& d_material) const;

  /// How shade() interpolates between light nodes: bilinear (4 nodes) or
  /// Catmull-Rom (16 nodes, clamped at the grid's edges; the sum is kept
  /// non-negative). Not stored: a reader's choice.
  enum class LightFilter { Bilinear, CatmullRom };
  LightFilter light_filter = LightFilter::CatmullRom;

  struct Light {
    Imath::V3f to_light;    ///< unit, the material's frame
    Imath::V3f irradiance;  ///< RGB, arriving at the cloth
  };
  /// What the point (x_mm, y_mm) of the repeat's top face shows toward
  /// `to_eye` (material frame) under `lights`, read at the level whose
  /// texels are `footprint_texels` level-0 texels wide (trilinear between
  /// levels, bilinear between texels, view nodes and light nodes; each view
  /// node read where parallax_depth_mm aligns it with the eye's ray). A
  /// colour-free material takes its yarn colours from `yarn` (null: the
  /// colours it was baked with), each texel tap with its own column's and
  /// row's colour; x_mm and y_mm may then span the colours' repeat.
  MarchResult shade(float x_mm, float y_mm, float footprint_texels, const Imath::V3f& to_eye,
                    std::span<const Light> lights, const YarnColours* yarn = nullptr) const;

  /// One light's light nodes and their weights (4 bilinear, or 16
  /// Catmull-Rom), the same for every view node.
  struct LightNodes {
    int count = 0;
    int node[16];
    float w[16];
    Imath::V3f irradiance;
  };
  LightNodes light_nodes(const Light& light) const;

  /// A lookup's four bilinear texel taps at one level and view node: each
  /// tap's index into the level's arrays, its weight, and the column and row
  /// the colours are read at (t = 0..3: column t & 1, row t >> 1).
  struct Taps {
    size_t texel[4];
    float w[4];
    int column[2], row[2];
  };
  Taps repeat_taps(float x_mm, float y_mm, int level, int view, const YarnColours* yarn) const;
  Taps crossing_taps(float x_mm, float y_mm, int level, int view, const YarnColours* yarn) const;

  /// The stored radiance of texel (x, y) of `level` for view node `view` and
  /// light node `node` (what the factorisation reconstructs), and its alpha.
  Imath::V3f texel_radiance(int level, int view, int node, int x, int y) const;
  float texel_alpha(int level, int view, int x, int y) const;
};

}  // namespace clothbake
