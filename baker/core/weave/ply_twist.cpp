#include "core/weave/ply_twist.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/util/random.h"

namespace clothbake {

namespace {

constexpr float k_pi = std::numbers::pi_v<float>;

/// Whole turns of the bundles per repeat, so the texture stays periodic.
float turns_per_repeat(float repeat_mm, float pitch_mm) {
  return std::max(1.0f, std::round(repeat_mm / pitch_mm));
}

}  // namespace

PlyTwist::PlyTwist(const ClothSpec& spec, Imath::V2f weave_mm)
    : m_seed(spec.seed),
      m_weave_mm(weave_mm),
      m_warp_turns(turns_per_repeat(weave_mm.y, spec.warp.ply_pitch_mm)),
      m_weft_turns(turns_per_repeat(weave_mm.x, spec.weft.ply_pitch_mm)) {}

float PlyTwist::phase(bool warp, int weave_yarn, float along_mm) const {
  // The draw's key holds the family as the volume's YarnFamily numbers it
  // (warp 1, weft 2; volume_generator.cpp checks that they still do).
  const uint64_t family = warp ? 1 : 2;
  const float repeat_mm = warp ? m_weave_mm.y : m_weave_mm.x;
  const float turns = warp ? m_warp_turns : m_weft_turns;
  const float phase0 =
      2.0f * k_pi * unit_float(hash_key(m_seed, rng_stream::phase, family, weave_yarn));
  return phase0 + 2.0f * k_pi * turns * along_mm / repeat_mm;
}

}  // namespace clothbake
