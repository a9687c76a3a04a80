#include "core/fiber/fiber_shader.h"

#include "core/util/random.h"

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

std::unique_ptr<FiberShader> make_object_fiber_shader(FiberModelKind kind, float aspect,
                                                      float exponent, int samples,
                                                      uint64_t render_seed, uint64_t object) {
  return std::make_unique<FiberShader>(kind, aspect, exponent, samples,
                                       hash_key(render_seed, rng_stream::fiber_table, object));
}

}  // namespace clothbake
