#pragma once
/// The volume texture: a periodic 3-D grid of cells (PAPER.md s.2).
///
/// Texture space: x along the weft, y along the warp, z up through the cloth,
/// in millimetres. The grid covers one weave repeat, [0, size.x) x [0, size.y)
/// x [0, size.z]; z = size.z is the top face (the cloth surface a quad maps to)
/// and z = 0 the bottom. Cell (i, j, k) is centred at ((i+.5)dx, (j+.5)dy,
/// (k+.5)dz); k = 0 is the bottom layer. x and y wrap; z does not.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Imath/ImathVec.h>

namespace clothbake {

/// Which yarn family a cell's fibres belong to.
enum class YarnFamily : uint8_t { None = 0, Warp = 1, Weft = 2 };

/// One cell: density rho, fibre tangent v and shading coefficients f.
struct Cell {
  float density = 0.0f;         ///< rho in [0, 1]: fraction of the cell occupied by fibre
  Imath::V3f tangent{0, 0, 0};  ///< unit fibre direction in texture space; zero where rho = 0
  Imath::V3f diffuse{0, 0, 0};  ///< diffuse colour (linear RGB albedo)
  float specular = 0.0f;        ///< specular strength
  float exponent = 0.0f;        ///< Phong exponent
  YarnFamily family = YarnFamily::None;
};

class VolumeTexture {
 public:
  VolumeTexture() = default;
  VolumeTexture(int nx, int ny, int nz, const Imath::V3f& size_mm);

  int nx() const { return m_nx; }
  int ny() const { return m_ny; }
  int nz() const { return m_nz; }
  size_t cell_count() const { return m_cells.size(); }
  /// Extent of one repeat in millimetres (x, y) and the cloth thickness (z).
  const Imath::V3f& size_mm() const { return m_size_mm; }
  /// Edge lengths of one cell in millimetres.
  Imath::V3f cell_size_mm() const {
    return {m_size_mm.x / m_nx, m_size_mm.y / m_ny, m_size_mm.z / m_nz};
  }

  /// Periodic in i and j; k must be in [0, nz).
  const Cell& at(int i, int j, int k) const { return m_cells[index(i, j, k)]; }
  Cell& at(int i, int j, int k) { return m_cells[index(i, j, k)]; }
  size_t index(int i, int j, int k) const {
    int iw = ((i % m_nx) + m_nx) % m_nx, jw = ((j % m_ny) + m_ny) % m_ny;
    return (size_t(k) * m_ny + jw) * m_nx + iw;
  }
  /// Cell at indices already inside the grid (0 <= i < nx, ...): no wrapping.
  const Cell& at_wrapped(int i, int j, int k) const {
    return m_cells[(size_t(k) * m_ny + j) * m_nx + i];
  }
  const std::vector<Cell>& cells() const { return m_cells; }

  /// 64-bit hash of every field of every cell (and the grid's shape), for
  /// determinism checks: equal hashes for equal contents, padding ignored.
  uint64_t content_hash() const;

 private:
  int m_nx = 0, m_ny = 0, m_nz = 0;
  Imath::V3f m_size_mm{0, 0, 0};
  std::vector<Cell> m_cells;  // x fastest, then y, then z
};

}  // namespace clothbake
