#pragma once
/// Counter-based random numbers: every random value is a pure function of
/// (seed, stream, index...), so results never depend on thread count or on the
/// order in which cells or pixels are visited. No generator state is shared.

#include <cstdint>

namespace clothbake {

/// SplitMix64 finaliser: a fast 64-bit mixer with full avalanche.
constexpr uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Hash any number of integers into one 64-bit key.
template <typename... Ints>
constexpr uint64_t hash_key(uint64_t first, Ints... rest) {
  uint64_t h = mix64(first);
  ((h = mix64(h ^ static_cast<uint64_t>(rest))), ...);
  return h;
}

/// Uniform float in [0, 1) from the top 24 bits of a key.
constexpr float unit_float(uint64_t key) {
  return static_cast<float>(key >> 40) * (1.0f / 16777216.0f);
}

/// Uniform double in [0, 1) from the top 53 bits of a key.
constexpr double unit_double(uint64_t key) {
  return static_cast<double>(key >> 11) * (1.0 / 9007199254740992.0);
}

/// The tags that keep random streams apart: each use of a seed hashes its
/// own tag in, hash_key(seed, rng_stream::x, ...), so no two uses draw the
/// same numbers. Each tag is its name in ASCII. Changing one changes every
/// output that draws from it (and the stored reference images).
namespace rng_stream {
constexpr uint64_t noise = 0x6e6f697365ull;        ///< "noise": yarn-surface noise (generator)
constexpr uint64_t phase = 0x7068617365ull;        ///< "phase": ply phase per yarn (generator)
constexpr uint64_t spread = 0x737072656164ull;     ///< "spread": fibre-direction spread (generator)
constexpr uint64_t shade = 0x7368616465ull;        ///< "shade": per-cell shading (generator)
constexpr uint64_t fiber_table = 0x7461626c65ull;  ///< "table": a fibre shader's table
constexpr uint64_t roulette = 0x726f756cull;       ///< "roul": the light roulette (march)
constexpr uint64_t probe = 0x70726f6265ull;        ///< "probe": the bake estimate's samples
constexpr uint64_t material = 0x6d6174ull;         ///< "mat": a material bake's texel samples
}  // namespace rng_stream

/// A tiny sequential generator for loops inside one task (e.g. the jittered
/// samples of one fibre evaluation). Seed it from hash_key of the task's ids.
class Rng {
 public:
  explicit constexpr Rng(uint64_t seed) : m_state(seed) {}
  constexpr uint64_t next_u64() { return mix64(m_state++); }
  constexpr float next_float() { return unit_float(next_u64()); }
  constexpr double next_double() { return unit_double(next_u64()); }

 private:
  uint64_t m_state;
};

}  // namespace clothbake
