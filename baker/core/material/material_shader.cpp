#include "core/material/material_shader.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/util/error.h"
#include "core/weave/cloth_colours.h"
#include "core/util/hex.h"

namespace clothbake {

namespace {
using Imath::V3f;

std::string str(float v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// World width of one pixel per unit distance from the camera.
float pixel_angle(const PinholeCamera& camera) {
  const float half = 0.5f * camera.fov_deg * std::numbers::pi_v<float> / 180.0f;
  const int across = camera.fov_axis == FovAxis::Horizontal ? camera.width : camera.height;
  return 2.0f * std::tan(half) / float(std::max(across, 1));
}
}  // namespace

MaterialOptics object_optics(const ClothScene& prepared, int o) {
  const Scene& scene = prepared.scene();
  const ClothObject& obj = scene.objects[size_t(o)];
  MaterialOptics optics;
  optics.extinction_per_mm = obj.extinction_per_mm;
  optics.shading = scene.settings.shading;
  optics.isotropic_albedo = obj.isotropic_albedo;
  optics.fiber_model = scene.settings.fiber_model;
  optics.fiber_samples = scene.settings.fiber_samples;
  optics.fiber_seed = scene.settings.seed;
  optics.step_cells = scene.settings.step_cells;
  optics.cutoff = scene.settings.cutoff;
  optics.light_roulette = scene.settings.light_roulette;
  double sum = 0.0, sum_aspect = 0.0;
  int n = 0;
  for (int q = 0; q < prepared.quad_count(o); ++q) {
    const V3f m = prepared.patch(o, q).frame(0.5f, 0.5f).mm_per_world;
    const float along = std::sqrt(std::fabs(m.x * m.y));
    if (!(along > 0.0f) || !std::isfinite(m.z / along) || !std::isfinite(m.y / m.x)) continue;
    sum += double(m.z / along);
    sum_aspect += double(std::fabs(m.y / m.x));
    ++n;
  }
  optics.depth_scale = n > 0 ? float(sum / n) : 1.0f;
  // A stretch within a part in 10^4 of none is none: the same bytes as a
  // material baked before the aspect was kept.
  const float aspect = n > 0 ? float(sum_aspect / n) : 1.0f;
  optics.aspect = std::fabs(aspect - 1.0f) < 1e-4f ? 1.0f : aspect;
  return optics;
}

void check_material_fits(const ClothScene& prepared, int o, const ClothMaterial& material) {
  const MaterialOptics have = object_optics(prepared, o);
  const MaterialOptics& want = material.optics;
  const std::string obj = "objects[" + std::to_string(o) + "]";
  if (material.colour_parts()) {
    // Colour-free: the cloth may differ in its yarn colours and nothing else.
    const ClothObject& object = prepared.scene().objects[size_t(o)];
    if (object.volume)
      throw InputError(obj + ".volume",
                       "is a VDB volume, whose colours are in its cells; the material is "
                       "colour-free, baked from a cloth spec: bake a material from this scene");
    const ClothDifference d = first_difference(colour_free(object.cloth), material.cloth);
    if (!d.field.empty())
      throw InputError(obj + ".cloth." + d.field,
                       "is " + d.a + ", the material's cloth has " + d.b +
                           " (once both are made colour-free): only the yarn colours may differ "
                           "from the material's; bake a material from this scene");
  } else {
    const uint64_t hash = prepared.volume(o).content_hash();
    if (hash != material.cloth_hash)
      throw InputError(obj + ".cloth",
                       "is not the material's cloth: its volume texture hashes to " + hex16(hash) +
                           ", the material's to " + hex16(material.cloth_hash));
  }
  const float rel = std::fabs(have.depth_scale / want.depth_scale - 1.0f);
  if (!(rel <= k_depth_scale_tolerance))
    throw InputError(obj + ".thickness_world",
                     "gives a depth scale (texture mm per world unit along the normal over "
                     "along the surface) of " + str(have.depth_scale) + ", the material's is " +
                         str(want.depth_scale) + " (" + str(rel * 100.0f) + "% apart, over " +
                         str(k_depth_scale_tolerance * 100.0f) +
                         "%): the thickness, repeats_per_uv or the mesh's UV scale differ; "
                         "bake a material from this scene");
  // The map's stretch between the texture's axes (optics.aspect) is not
  // checked: a garment's UV islands are stretched each their own way, and
  // the material shades them all at the stretch it was baked for, as the
  // add-on does (exact where the two agree; docs/design/material.md).
  if (std::fabs(have.extinction_per_mm / want.extinction_per_mm - 1.0f) > 1e-6f)
    throw InputError(obj + ".extinction_per_mm", "is " + str(have.extinction_per_mm) +
                                                     ", the material was baked at " +
                                                     str(want.extinction_per_mm));
  if (have.shading != want.shading)
    throw InputError("render.shading", "differs from the material's shading mode");
  if (have.shading == ShadingMode::Fiber && have.fiber_model != want.fiber_model)
    throw InputError("render.fiber_model", "differs from the material's fibre model");
  if (have.shading == ShadingMode::Isotropic && !(have.isotropic_albedo == want.isotropic_albedo))
    throw InputError(obj + ".isotropic_albedo", "differs from the material's");
}

SurfaceShader material_shader(const ClothScene& prepared,
                              const std::vector<const ClothMaterial*>& materials,
                              const MaterialLookupSettings& settings) {
  const Scene& scene = prepared.scene();
  const float angle = pixel_angle(scene.camera);
  const V3f eye = scene.camera.position_world;
  const float stratum = 1.0f / std::sqrt(float(std::max(scene.settings.spp, 1)));
  // Colour-free materials render in each object's own yarn colours.
  auto colours = std::make_shared<std::vector<YarnColours>>(materials.size());
  for (size_t o = 0; o < materials.size(); ++o)
    if (materials[o] && materials[o]->colour_parts())
      (*colours)[o] = materials[o]->colours_of(palette_of(scene.objects[o].cloth));
  return [&prepared, &scene, materials, colours, angle, eye, settings, stratum](
             int o, int q, float s, float t, const V3f& ray_dir_world, Rng& rng) {
    const ClothMaterial& mat = *materials[size_t(o)];
    const QuadPatch& patch = prepared.patch(o, q);
    const SurfaceFrame frame = patch.frame(s, t);
    const V3f p_world = patch.position_world(s, t);
    const V3f top = patch.texture_point(s, t);
    // The pixel's footprint on the surface: its width across the ray at this
    // distance, stretched by 1 / cos along the tilt; the level is taken from
    // the geometric mean of the two axes (an isotropic lookup of the
    // anisotropic footprint).
    const float cos_view = std::max(std::fabs(ray_dir_world.dot(frame.normal_world)), 0.02f);
    const float across_world = (p_world - eye).length() * angle;
    const float mm = std::sqrt(std::fabs(frame.mm_per_world.x * frame.mm_per_world.y));
    const float footprint_mm = across_world / std::sqrt(cos_view) * mm;
    // A level-0 texel: R per repeat, or R per thread when addressed per
    // crossing (the mean thread's width).
    const float texel_mm =
        mat.repeat_mm.x / float(mat.texels() * (mat.addressed() ? mat.crossings.ends : 1));
    const float footprint_texels = settings.footprint_scale * stratum * footprint_mm / texel_mm;

    ClothMaterial::Light lights[k_max_march_lights];
    size_t n = 0;
    for (const Light& light : scene.lights) {
      if (n == k_max_march_lights) break;
      V3f to_light_world, irradiance;
      // One point of an area light per hit, as the reference renderer draws.
      float u1 = 0.5f, u2 = 0.5f;
      if (light.sampled()) {
        u1 = rng.next_float();
        u2 = rng.next_float();
      }
      light.illuminate(p_world, to_light_world, irradiance, u1, u2);
      lights[n].to_light = mat.material_from_texture(frame.texture_from_world(to_light_world));
      lights[n].irradiance = irradiance;
      ++n;
    }
    const V3f to_eye = mat.material_from_texture(frame.texture_from_world(-ray_dir_world));
    return mat.shade(top.x, top.y, footprint_texels, to_eye,
                     std::span<const ClothMaterial::Light>(lights, n),
                     mat.colour_parts() ? &(*colours)[size_t(o)] : nullptr);
  };
}

}  // namespace clothbake
