#pragma once
/// What a cloth-material bake is asked to compute (docs/formats/material.md),
/// what its appearance depends on besides the cloth spec, and the ranges each
/// setting may take. The ranges are stated here once: the core checks them
/// (check_material_settings), the manifest reader, the command line and the
/// add-on (tests/addon/test_material_defaults.py) use them.

#include <cstdint>

#include <Imath/ImathVec.h>

#include "core/geometry/direction_grid.h"
#include "core/fiber/fiber_model.h"
#include "core/march/march_settings.h"
#include "core/weave/crossing_neighbourhoods.h"

namespace clothbake {

inline constexpr int k_min_material_texels = 1, k_max_material_texels = 1024;  ///< R, a power of 2
inline constexpr int k_min_material_directions = 2, k_max_material_directions = 32;  ///< K, KL
inline constexpr int k_min_material_spp = 1, k_max_material_spp = 1024;
inline constexpr float k_min_material_error = 0.0f, k_max_material_error = 1.0f;
inline constexpr int k_min_field_supersample = 1, k_max_field_supersample = 4;
/// Tangent nodes per side of the fibre table (0 turns the table off).
inline constexpr int k_min_fiber_tangent_nodes = 2, k_max_fiber_tangent_nodes = 256;

/// What a coefficient's three channels hold (docs/formats/material.md):
/// linear RGB, or the colour-free parts, specular and the diffuse of each yarn
/// family, to be multiplied by the yarn colours when the material renders.
enum class MaterialParts { Rgb, SpecularWarpWeft };

/// How a material's texels cover the cloth (docs/formats/material.md): the
/// whole repeat, R x R texels; or one block of R x R texels per distinct
/// crossing neighbourhood (crossing_neighbourhoods.h, plus 1), addressed
/// through a per-crossing index, so that its size follows the weave's
/// variety and not its repeat.
enum class MaterialAddress { Repeat, Crossings };

/// Crossings either side of a block's crossing that its light fields hold
/// (the context a shadow ray sees before it wraps).
inline constexpr int k_min_material_context = 1, k_max_material_context = 4;
/// Crossings of a class a block averages (its representative first).
inline constexpr int k_min_material_members = 1, k_max_material_members = 16;
inline constexpr int k_min_phase_bins = 1, k_max_phase_bins = 16;

/// How a material's light fields are read (light_fields.h): trilinear
/// between the cells' centres, or by a march through the sample's own layer
/// to the faces between layers. Auto: LayerMarch where a field cell of the
/// cloth's densest fibre is optically thick (LightFieldSet::resolve).
enum class LightFieldMethod { Auto, Interpolated, LayerMarch };

/// Optical depth across one field cell's longest edge, at the cloth's densest
/// cell, beyond which Auto reads the fields by LayerMarch (the paper's cloth:
/// 0.45 to 0.55; a 2.12 mm yarn at 8 cells a thread: 2.2 to 5.3).
inline constexpr float k_layer_march_cell_depth = 1.0f;

/// Which part of a sharded bake a material is (material_shard.h): part
/// `index` (0-based; the CLI's --shard counts from 1) of `count`. A count of
/// 1 is the whole bake.
struct MaterialShard {
  int index = 0;
  int count = 1;
  bool whole() const { return count == 1; }
};

/// The sampling and compression of the table.
struct MaterialSettings {
  int texels = 32;            ///< R: texels per repeat side at level 0, a power of 2
  int directions = 16;        ///< K: view nodes per side of each hemisphere's grid
  int light_directions = 10;  ///< KL: light nodes per side of each hemisphere's grid
  int spp = 2;                ///< jittered samples per texel and view node
  /// Light nodes' layout: drawn toward the horizon, where grazing light
  /// changes fastest (direction_grid.h), or the plain square.
  DirectionMap light_map = DirectionMap::HemiOctahedralHorizon;
  float max_error = 0.05f;    ///< per view node: relative RMSE of the factorisation, level 0
  int field_supersample = 2;  ///< light-transmittance field points per cell edge
  /// How the light fields are read (light_fields.h); Auto is settled by the
  /// bake from the cloth's optical depth per field cell.
  LightFieldMethod light_fields = LightFieldMethod::Auto;
  /// Fibre response per light node tabulated over k x k tangent directions
  /// per view node (node_march.h, FiberLightTable); 0: the fibre model per
  /// cell and light node.
  int fiber_tangent_nodes = 32;
  /// Read each view node where its ray meets the eye's at a depth fitted to
  /// the material (view_parallax.h); off: every node at the eye's x.
  bool view_parallax = true;
  uint64_t seed = 1;
  /// Whole repeat (texels: R per repeat side) or per crossing (texels: R per
  /// crossing side, one block per plus-1 class).
  MaterialAddress address = MaterialAddress::Repeat;
  /// Addressed per crossing: crossings either side of a block's that its
  /// light fields span.
  int context = 2;
  /// Addressed per crossing: what makes two crossings one class (one block).
  CrossingStencil stencil = CrossingStencil::Plus1;
  /// Addressed per crossing: crossings of each class the block averages,
  /// spread over the class (1: its representative alone).
  int members = 1;
  /// Addressed per crossing: bins of the ply phase of the yarn on top at a
  /// crossing, each bin its own block of the class (1: the phase is not in
  /// the class). The generator draws that phase per yarn; at a thread per
  /// pixel or two it is what makes one seed's cloth differ from another's
  /// (docs/design/material.md, "The per-pixel floor is the ply phase").
  int phase_bins = 1;
  /// Colour-free parts need fibre shading and a volume made colour-free
  /// (core/weave/cloth_colours.h); the command chooses.
  MaterialParts parts = MaterialParts::Rgb;
};

/// Everything besides the volume texture and the fibre model that changes
/// what a surface point shows: a scene object that differs in any of these
/// cannot use the material (it is refused, naming the field).
struct MaterialOptics {
  /// Texture mm per world unit along the normal over that along the surface
  /// (mm_per_world.z / mm_per_world.x, surface_frame.h): how the slab is
  /// stretched in depth. Directions in the material's frame are carried to
  /// texture space by (x, y, z * depth_scale).
  float depth_scale = 1.0f;
  /// Texture mm per world unit along texture y over along x (mm_per_world.y
  /// / mm_per_world.x): how the map stretches the repeat between its axes
  /// (a draft of 91 ends and 480 picks at one repeats_per_uv on square UVs:
  /// 5.3). The material's frame is texture space (z scaled by depth_scale);
  /// the fibres are shaded in the world's true angles, which this carries
  /// them to (ClothMaterial::local_from_material). 1: no stretch.
  float aspect = 1.0f;
  float extinction_per_mm = 40.0f;
  ShadingMode shading = ShadingMode::Fiber;
  Imath::V3f isotropic_albedo{0.8f, 0.8f, 0.8f};
  FiberModelKind fiber_model = FiberModelKind::Table;
  int fiber_samples = 64;
  uint64_t fiber_seed = 1;  ///< seeds the fibre table (the scene's render seed)
  float step_cells = 0.5f;
  float cutoff = 1e-3f;
  float light_roulette = 0.25f;
};

}  // namespace clothbake
