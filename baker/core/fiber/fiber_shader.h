#pragma once
/// One front door to the three forms of the fibre model (fiber_model.h,
/// fiber_table.h), as the renderer uses it: built once per cloth (aspect,
/// exponent), then evaluated many times from any thread.

#include <cstdint>
#include <memory>

#include "core/fiber/fiber_model.h"
#include "core/fiber/fiber_table.h"

namespace clothbake {

class FiberShader {
 public:
  /// Builds the table when kind == Table (deterministic, parallel).
  FiberShader(FiberModelKind kind, float aspect, float exponent, int samples, uint64_t seed);

  /// All vectors in one common orthonormal space, unit, pointing away from
  /// the fibre. `sample_seed` picks the jitter of the direct ellipsoid model.
  FiberResponse eval(const Imath::V3f& tangent, const Imath::V3f& to_light,
                     const Imath::V3f& to_eye, uint64_t sample_seed) const {
    switch (m_kind) {
      case FiberModelKind::Table:
        return m_table->eval(tangent, to_light, to_eye);
      case FiberModelKind::KajiyaKay:
        return kajiya_kay_fiber(tangent, to_light, to_eye, m_params.exponent);
      case FiberModelKind::Ellipsoid:
      default:
        return ellipsoid_fiber(tangent, to_light, to_eye, m_params, sample_seed);
    }
  }
  FiberModelKind kind() const { return m_kind; }

 private:
  FiberModelKind m_kind;
  EllipsoidFiberParams m_params;
  std::shared_ptr<const FiberTable> m_table;
};

/// The fibre shader of cloth object `object` in a scene whose render seed is
/// `render_seed`: the table is seeded by both, so every route that prepares
/// that object (render, bake, material) builds the same table.
std::unique_ptr<FiberShader> make_object_fiber_shader(FiberModelKind kind, float aspect,
                                                      float exponent, int samples,
                                                      uint64_t render_seed, uint64_t object);

}  // namespace clothbake
