#pragma once
/// Everything that defines one woven cloth's volume texture (PAPER.md s.2).
/// Lengths are millimetres of texture space, angles degrees, colours linear
/// RGB. Every field has the default documented in docs/formats/cloth-spec.md; the I/O
/// layer fills these structs from JSON, the core never parses.

#include <cstdint>
#include <string>
#include <vector>

#include <Imath/ImathVec.h>

#include "core/weave/weave.h"

namespace clothbake {

/// One yarn family (warp or weft).
struct YarnSpec {
  float spacing_mm = 0.5f;     ///< centre-to-centre distance of neighbouring yarns
  float width_mm = 0.44f;      ///< full width of the elliptical cross-section, in the cloth plane
  float thickness_mm = 0.18f;  ///< full height of the cross-section, across the cloth
  Imath::V3f color{0.60f, 0.09f, 0.08f};  ///< diffuse albedo, linear RGB in [0, 1]
  float twist_deg = 28.0f;    ///< angle of the fibres to the yarn axis (ply twist), [0, 89]
  float ply_pitch_mm = 1.0f;  ///< yarn length of one full turn of the two twisted bundles
  /// Per-thread values, each empty (every thread takes the family's value
  /// above) or one per thread, a shorter list repeating: the repeat of the
  /// cloth is the least common multiple of the draft's and these lengths.
  std::vector<Imath::V3f> colors;     ///< diffuse albedo per thread, linear RGB
  std::vector<float> spacings_mm;     ///< distance from this thread's centre to the next one's
  std::vector<float> widths_mm;       ///< full in-plane width per thread
};

/// Density rho (fraction of a cell occupied by fibre, PAPER.md s.2 "first element").
struct DensitySpec {
  float core = 1.0f;        ///< rho at a yarn's centre line, (0, 1]
  float edge = 0.45f;       ///< rho at a yarn's boundary, [0, core]
  float falloff = 1.5f;     ///< exponent p of (1 - r^2)^p from centre to edge, > 0
  float top_factor = 0.7f;  ///< multiplier of rho at the cloth's top face (1 at its bottom), (0, 1]
  float noise_amplitude = 0.2f;  ///< relative amplitude of the seeded spatial noise, [0, 1]
  float noise_scale_mm = 0.06f;  ///< feature size of that noise, > 0
};

/// Shading coefficients f per cell (PAPER.md s.2 "third element").
struct ShadingSpec {
  float specular_top = 0.55f;     ///< specular strength at the top face
  float specular_bottom = 0.08f;  ///< specular strength at the bottom face
  float diffuse_top = 0.65f;      ///< multiplier of the yarn colour at the top face
  float diffuse_bottom = 1.0f;    ///< multiplier of the yarn colour at the bottom face
  float exponent = 24.0f;         ///< Phong exponent, > 0 (one value for the cloth)
  float variation = 0.15f;        ///< relative seeded random variation of both strengths, [0, 1]
  float fiber_aspect = 8.0f;      ///< ellipsoid aspect of the fibre model, >= 1
};

/// Grid of cells over ONE weave repeat (the texture tiles periodically in x, y).
struct ResolutionSpec {
  /// 0 = automatic: 64 cells per named pattern's repeat (times the repeats of
  /// it the colour sequence spans), and for an explicit draft
  /// max(64, cells_per_thread x threads): see resolved_resolution().
  int cells_x = 0;      ///< cells across the repeat along x (weft direction)
  int cells_y = 0;      ///< cells across the repeat along y (warp direction)
  int layers = 16;      ///< cells through the cloth's thickness (z)
  int supersample = 2;  ///< s: each cell's rho averages s^3 sub-cell points, [1, 8]
  int cells_per_thread = 8;  ///< automatic cells per warp end (x) and per weft pick (y) of a draft
};

/// Pattern name of a homogeneous slab instead of a weave: every cell has
/// rho = density.core, tangent +x, the warp colour times shading.diffuse_top
/// and shading.specular_top, no noise or variation. For analytic checks.
inline constexpr const char* k_uniform_pattern = "uniform";

struct ClothSpec {
  std::string pattern = "plain";  ///< named draft or "uniform"; ignored when `draft` is non-empty
  std::vector<std::vector<int>> draft;  ///< explicit draft (rows = picks, 1 = warp up)
  /// Where the draft came from when it was read from a weaving file (a WIF):
  /// text for reports only, not part of the texture.
  std::string draft_source;
  std::string draft_program;  ///< the program that wrote that file, when it says
  YarnSpec warp;                        ///< runs along +y
  YarnSpec weft{0.5f, 0.44f, 0.18f, {0.55f, 0.42f, 0.10f}, 28.0f, 1.0f, {}, {}, {}};  ///< runs along +x
  float crimp = 1.0f;  ///< over/under amplitude; 1 = yarns just touch at crossings, [0, 2]
  float angle_spread_deg = 6.0f;  ///< std. deviation of the random fibre-direction perturbation
  DensitySpec density;
  ShadingSpec shading;
  ResolutionSpec resolution;
  uint64_t seed = 1;  ///< seeds every random choice; same seed, same bytes
};

/// Checks ranges and consistency; throws InputError naming the field.
void validate(const ClothSpec& spec);

/// The draft the spec weaves: `draft`, else the named pattern (the uniform
/// slab sized as a plain weave's 2 x 2 repeat).
WeaveDraft draft_of(const ClothSpec& spec);

/// The resolution with the automatic (0) cells_x / cells_y filled in.
ResolutionSpec resolved_resolution(const ClothSpec& spec);

}  // namespace clothbake
