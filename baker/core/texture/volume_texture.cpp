#include "core/texture/volume_texture.h"

#include <bit>

#include "core/util/random.h"

namespace clothbake {

VolumeTexture::VolumeTexture(int nx, int ny, int nz, const Imath::V3f& size_mm)
    : m_nx(nx), m_ny(ny), m_nz(nz), m_size_mm(size_mm), m_cells(size_t(nx) * ny * nz) {}

uint64_t VolumeTexture::content_hash() const {
  uint64_t h =
      hash_key(uint64_t(m_nx), uint64_t(m_ny), uint64_t(m_nz), std::bit_cast<uint32_t>(m_size_mm.x),
               std::bit_cast<uint32_t>(m_size_mm.y), std::bit_cast<uint32_t>(m_size_mm.z));
  auto add = [&h](float v) { h = mix64(h ^ std::bit_cast<uint32_t>(v)); };
  for (const Cell& c : m_cells) {
    add(c.density);
    for (int a = 0; a < 3; ++a) add(c.tangent[a]);
    for (int a = 0; a < 3; ++a) add(c.diffuse[a]);
    add(c.specular);
    add(c.exponent);
    h = mix64(h ^ uint64_t(c.family));
  }
  return h;
}

}  // namespace clothbake
