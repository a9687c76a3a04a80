#pragma once
/// The view march of volume_march.h serving every light node at once: one
/// walk through the cells along the view ray (the skeleton both share,
/// sample_march.h), and at each sample the
/// transmittance toward all light nodes from their fields (light_fields.h)
/// and each cell's fibre response toward all of them. Returns, per light
/// node, the radiance toward the eye per unit irradiance from that node:
/// exactly what march_view_ray returns for one light of irradiance 1 whose
/// transmittance comes from the same field (same seed, same samples, same
/// roulette decisions, which depend on the view alone).

#include <cstdint>
#include <span>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/fiber/fiber_shader.h"
#include "core/march/march_settings.h"
#include "core/march/sample_march.h"
#include "core/material_bake/light_fields.h"
#include "core/texture/volume_texture.h"
#include "core/weave/thread_layout.h"

namespace clothbake {

/// The fibre model's response toward every light node for one view node, as
/// a function of the fibre tangent alone: tabulated on a hemi-octahedral grid
/// of tangents (the response is even in the tangent, so one hemisphere), so
/// that a cell's response toward all light nodes is one set of bilinear
/// weights applied to contiguous rows instead of one fibre evaluation per
/// light node. Built once per view node; its interpolation error is measured
/// in tests/core/material_bake/material_bake_test.cpp.
class FiberLightTable {
 public:
  /// `k` x `k` tangent nodes; evaluates `shader` k^2 x light-node times.
  void build(const FiberShader& shader, std::span<const Imath::V3f> to_light_local,
             const Imath::V3f& to_eye_local, int k);
  /// Diffuse and specular factors toward every light node for a unit
  /// tangent (material frame): diffuse[l], specular[l].
  void eval(const Imath::V3f& tangent_local, float* diffuse, float* specular) const;
  int k() const { return m_k; }

 private:
  int m_k = 0;
  size_t m_lights = 0;
  std::vector<float> m_diffuse, m_specular;  // [(j * k + i) * lights + l]
};

/// The view march of one view node for every light node: the ray and its
/// sampling (sample_march.h), and what each sample is lit and shaded by.
struct NodeMarchInput : SampleMarchInput {
  const FiberShader* shader = nullptr;
  const LightFieldSet* fields = nullptr;  ///< one field per light node
  /// The fibre response per light node by tangent (null: the fibre model
  /// itself, per cell and light node).
  const FiberLightTable* fiber_table = nullptr;
  /// Per light node, unit, the local (shading) frame: the material's frame
  /// through ClothMaterial::local_from_material.
  std::span<const Imath::V3f> to_light_local;
  Imath::V3f to_eye_local;  ///< unit, the local (shading) frame
  /// Carry fibre tangents to the local frame:
  /// (t.x * sqrt(aspect), t.y / sqrt(aspect), t.z / depth_scale), normalised.
  float depth_scale = 1.0f;
  float sqrt_aspect = 1.0f;
  ShadingMode shading = ShadingMode::Fiber;
  Imath::V3f isotropic_albedo{0.8f, 0.8f, 0.8f};
  /// Colour-free parts (fibre shading, a volume made colour-free): each
  /// cell's response as (specular, warp diffuse, weft diffuse) instead of RGB,
  /// the diffuse divided by k_neutral_albedo (cloth_colours.h).
  bool colour_parts = false;
  /// Colour-free parts: the cloth's threads and the sample's own warp end
  /// and weft pick (the threads owning its entry point). A cell of another
  /// thread, which a ray running across the threads reaches, is counted
  /// apart (radiance_next), since it shows that thread's colour.
  const ThreadLayout* warp_threads = nullptr;
  const ThreadLayout* weft_threads = nullptr;
  int own_end = 0, own_pick = 0;
};

/// Work space a thread reuses between marches (no allocation per ray).
/// With a deterministic fibre model (the table, Kajiya-Kay) a cell's
/// response toward every light node depends on the view alone, and the rays
/// of one view node cross the same cells again and again: the responses are
/// kept per cell, tagged with `view_tag`, and reused while the tag is the same.
struct NodeMarchScratch {
  std::vector<Imath::V3f> reflect;       ///< per light node: the current cell's response
  std::vector<float> transmittance;      ///< per light node: at the current sample
  std::vector<float> response;           ///< [cell * lights + l] * 2: diffuse, specular factors
  std::vector<uint32_t> tag;             ///< per cell: the view_tag its responses are for (0: none)
  uint32_t view_tag = 0;                 ///< set by the caller, unique per view node, > 0
  std::vector<float> diffuse, specular;  ///< per light node, from the FiberLightTable
};

struct NodeMarchCounts {
  uint64_t samples = 0;            ///< view samples shaded
  uint64_t fiber_evaluations = 0;  ///< fibre-model evaluations (cells x light nodes)
};

/// Adds each light node's radiance into radiance[l] (RGB, l < the node
/// count) and returns the view's transmittance (0 when stopped at the cutoff).
/// Colour-free parts: the parts of the sample's own threads into radiance[l],
/// those of other threads into radiance_next[l] (which must then be given).
float march_view_ray_all_lights(const NodeMarchInput& in, Imath::V3f* radiance,
                                NodeMarchScratch& scratch, NodeMarchCounts& counts,
                                Imath::V3f* radiance_next = nullptr);

}  // namespace clothbake
