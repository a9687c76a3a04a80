#include "core/fiber/fiber_shader.h"

namespace clothbake {

FiberShader::FiberShader(FiberModelKind kind, float aspect, float exponent, int samples,
                         uint64_t seed)
    : m_kind(kind) {
  m_params.aspect = aspect;
  m_params.exponent = exponent;
  m_params.samples = samples;
  if (kind == FiberModelKind::Table) {
    FiberTableParams tp;
    tp.fiber = m_params;
    tp.seed = seed;
    m_table = std::make_shared<const FiberTable>(FiberTable::build(tp));
  }
}

}  // namespace clothbake
