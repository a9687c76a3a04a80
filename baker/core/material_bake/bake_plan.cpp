#include "core/material_bake/bake_plan.h"

#include <cstdio>

#include "core/material_bake/bake_rules.h"
#include "core/material_bake/material_bake.h"

namespace clothbake {

namespace {
std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 19)) >> 20) + " MiB"; }

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

/// The bytes the bake holds before its table grows, and its blocks (0: the whole repeat).
struct Footprint {
  uint64_t bytes = 0;
  int blocks = 0;
};

Footprint footprint(const MaterialSource& source, const MaterialSettings& s, int threads) {
  const ClothMaterial material = unbaked_material(source, s);
  return {material_bake_fixed_bytes(material, *source.volume, threads),
          material.addressed() ? material.layout().blocks : 0};
}

std::string blocks_text(int blocks) {
  return std::to_string(blocks) + (blocks == 1 ? " block" : " blocks");
}

std::string mode_name(const MaterialSettings& s, int blocks) {
  return s.address == MaterialAddress::Crossings
             ? "per crossing at " + std::to_string(s.texels) + " texels (" + blocks_text(blocks) +
                   ")"
             : "the whole repeat at " + std::to_string(s.texels) + " texels";
}
}  // namespace

BakePlan plan_material_bake(const MaterialSource& source, const MaterialSettings& settings,
                            const BakeRequest& request, int ends, int picks, int threads,
                            uint64_t budget_bytes) {
  BakePlan plan;
  plan.settings = settings;
  MaterialSettings& s = plan.settings;
  if (request.texels) s.texels = *request.texels;
  auto finish = [&](std::string why) {
    const Footprint f = footprint(source, s, threads);
    plan.fixed_bytes = f.bytes;
    plan.fits = plan.fixed_bytes <= budget_bytes;
    plan.mode = mode_name(s, f.blocks);
    plan.reason = why;
    plan.why = plan.mode + ": " + why + "; the bake holds " + mib(plan.fixed_bytes) +
               " before its table grows";
    return plan;
  };
  if (request.address) {
    s.address = *request.address;
    return finish("as asked");
  }
  s.address = MaterialAddress::Repeat;
  if (s.parts != MaterialParts::SpecularWarpWeft)
    return finish("RGB parts: per crossing needs colour-free ones");
  const TexelAdvice advice = texel_advice(s, ends, picks);
  const uint64_t whole = footprint(source, s, threads).bytes;
  std::string why;
  if (advice.too_few())
    why = "the whole repeat spans " + std::to_string(advice.threads_across) +
          " threads: " + fixed(advice.texels_per_thread, 2) + " texels a thread at " +
          std::to_string(s.texels) + ", below " + fixed(k_min_texels_per_thread, 0);
  else if (whole > budget_bytes)
    why = "the whole repeat at " + std::to_string(s.texels) + " texels would hold " + mib(whole) +
          ", over the budget of " + mib(budget_bytes);
  else if (advice.known())
    return finish(fixed(advice.texels_per_thread, 1) + " texels a thread, within the budget");
  else
    return finish("within the budget");
  s.address = MaterialAddress::Crossings;
  if (request.texels) return finish(why);
  s.texels = k_auto_crossing_texels;
  // Fewer texels a crossing before a refusal: a 641 x 641 draft's volume
  // alone holds 16 GB of the 18 a 24 GB machine gives, and at 4 texels its
  // blocks take the 2 GB left (docs/design/material.md, "What the bake chooses").
  const uint64_t at_default = footprint(source, s, threads).bytes;
  if (at_default > budget_bytes) {
    s.texels = k_auto_crossing_min_texels;
    if (footprint(source, s, threads).bytes <= budget_bytes)
      why += "; at " + std::to_string(k_auto_crossing_texels) +
             " texels a crossing it would hold " + mib(at_default) + ", over the budget of " +
             mib(budget_bytes);
    else
      s.texels = k_auto_crossing_texels;  // neither fits: refused with the 8's figures
  }
  return finish(why);
}

MemoryAdvice advice_for_memory(const MaterialSource& source, const BakePlan& plan, int threads,
                               uint64_t budget_bytes) {
  if (source.parts != MaterialParts::SpecularWarpWeft) return {};
  MemoryAdvice advice{plan.settings, {}};
  MaterialSettings& s = advice.settings;
  s.address = MaterialAddress::Crossings;
  for (int texels : {k_auto_crossing_texels, 4, 2}) {
    if (plan.settings.address == MaterialAddress::Crossings && texels >= plan.settings.texels)
      continue;
    s.texels = texels;
    const Footprint f = footprint(source, s, threads);
    if (f.bytes <= budget_bytes) {
      advice.text = "--address crossings --texels " + std::to_string(texels) + ": " +
                    blocks_text(f.blocks) + ", the bake holds about " + mib(f.bytes);
      return advice;
    }
  }
  return {};
}

}  // namespace clothbake
