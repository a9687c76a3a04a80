#include "core/bake/scene_fingerprint.h"

#include <bit>
#include <cstdio>

#include "core/util/hex.h"
#include "core/util/random.h"

namespace clothbake {

namespace {

/// Folds values into one 64-bit hash; floats by their bits, so the hash is
/// exact (no rounding) and the same on every platform with IEEE floats.
class Fingerprint {
 public:
  void add(uint64_t x) { m_h = hash_key(m_h, x); }
  void add(int x) { add(uint64_t(uint32_t(x))); }
  void add(float x) { add(uint64_t(std::bit_cast<uint32_t>(x))); }
  void add(const Imath::V3f& v) {
    add(v.x);
    add(v.y);
    add(v.z);
  }
  void add(const Imath::V2f& v) {
    add(v.x);
    add(v.y);
  }
  void add(const std::string& s) {
    add(uint64_t(s.size()));
    for (char c : s) add(uint64_t(uint8_t(c)));
  }
  uint64_t value() const { return m_h; }

 private:
  uint64_t m_h = 0x636C6F746862616Bull;  // "clothbak"
};

void add_yarn(Fingerprint& f, const YarnSpec& y) {
  f.add(y.spacing_mm);
  f.add(y.width_mm);
  f.add(y.thickness_mm);
  f.add(y.color);
  f.add(y.twist_deg);
  f.add(y.ply_pitch_mm);
  // Per-thread lists only when given, so a spec without them keeps the
  // fingerprint it always had.
  if (!y.colors.empty() || !y.spacings_mm.empty() || !y.widths_mm.empty()) {
    f.add(uint64_t(y.colors.size()));
    for (const Imath::V3f& c : y.colors) f.add(c);
    f.add(uint64_t(y.spacings_mm.size()));
    for (float v : y.spacings_mm) f.add(v);
    f.add(uint64_t(y.widths_mm.size()));
    for (float v : y.widths_mm) f.add(v);
  }
}

// Every field of ClothSpec: keep in step with core/weave/cloth_spec.h.
void add_cloth(Fingerprint& f, const ClothSpec& c) {
  f.add(c.pattern);
  f.add(uint64_t(c.draft.size()));
  for (const std::vector<int>& row : c.draft) {
    f.add(uint64_t(row.size()));
    for (int v : row) f.add(v);
  }
  add_yarn(f, c.warp);
  add_yarn(f, c.weft);
  f.add(c.crimp);
  f.add(c.angle_spread_deg);
  const DensitySpec& d = c.density;
  for (float v : {d.core, d.edge, d.falloff, d.top_factor, d.noise_amplitude, d.noise_scale_mm})
    f.add(v);
  const ShadingSpec& s = c.shading;
  for (float v : {s.specular_top, s.specular_bottom, s.diffuse_top, s.diffuse_bottom, s.exponent,
                  s.variation, s.fiber_aspect})
    f.add(v);
  // The resolution as generated (automatic cells filled in): a named
  // pattern's automatic 64 hashes as the explicit 64 it once was.
  const ResolutionSpec r = resolved_resolution(c);
  for (int v : {r.cells_x, r.cells_y, r.layers, r.supersample}) f.add(v);
  f.add(c.seed);
}

}  // namespace

std::string scene_fingerprint(const Scene& scene) {
  Fingerprint f;
  // Objects: geometry, mapping into the texture, and the cloth itself.
  f.add(uint64_t(scene.objects.size()));
  for (const ClothObject& o : scene.objects) {
    const QuadMesh& m = o.mesh;
    f.add(uint64_t(m.positions_world.size()));
    for (const Imath::V3f& p : m.positions_world) f.add(p);
    f.add(uint64_t(m.uvs.size()));
    for (const Imath::V2f& uv : m.uvs) f.add(uv);
    f.add(uint64_t(m.quads.size()));
    for (const QuadMesh::Quad& q : m.quads)
      for (int c = 0; c < 4; ++c) {
        f.add(q.position[c]);
        f.add(q.uv[c]);
      }
    f.add(o.repeats_per_uv);
    f.add(o.thickness_world);
    f.add(o.extinction_per_mm);
    f.add(o.isotropic_albedo);
    add_cloth(f, o.cloth);
    // A texture read from a VDB: its contents, so an edited file is a new scene.
    if (o.volume) f.add(o.volume->content_hash());
  }
  // Lights: only what the light's type uses.
  f.add(uint64_t(scene.lights.size()));
  for (const Light& l : scene.lights) {
    f.add(int(l.type));
    f.add(l.type == LightType::Directional ? l.to_light_world : l.position_world);
    f.add(l.color);
    f.add(l.intensity);
    if (l.type == LightType::Spot || l.type == LightType::Area) f.add(l.axis_world);
    if (l.type == LightType::Spot) {
      f.add(l.spot_cos_half_angle);
      f.add(l.spot_smooth);
      // Off its default only, so that every scene written before the field
      // keeps its fingerprint.
      if (!l.spot_axis_cosine) f.add(std::string("no axis cosine"));
    }
    if (l.type == LightType::Area) {
      f.add(l.side_world);
      f.add(int(l.area_shape));
      f.add(l.area_width);
      f.add(l.area_height);
    }
  }
  // Render settings that change a march (not spp: the bake has its own).
  const RenderSettings& s = scene.settings;
  f.add(s.step_cells);
  f.add(int(s.fiber_model));
  f.add(s.fiber_samples);
  f.add(int(s.transmittance));
  f.add(int(s.shading));
  f.add(s.cutoff);
  f.add(s.seed);
  f.add(s.light_roulette);  // changes the bake's bytes (not its expectation), as the seed does

  return hex16(f.value());
}

}  // namespace clothbake
