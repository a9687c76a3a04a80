#include "core/geometry/mesh_summary.h"

#include <algorithm>
#include <limits>

namespace clothbake {

MeshSummary summarize_mesh(const QuadMesh& mesh) {
  MeshSummary s;
  const float inf = std::numeric_limits<float>::infinity();
  Imath::V3f lo(inf), hi(-inf);
  Imath::V2f uv_lo(inf), uv_hi(-inf);
  // Sums in double: a mesh of many quads must not lose its small ones.
  double centre[3] = {0, 0, 0};
  size_t counted = 0;
  const auto n_positions = mesh.positions_world.size(), n_uvs = mesh.uvs.size();
  for (const QuadMesh::Quad& q : mesh.quads) {
    bool in_range = true;
    for (int c = 0; c < 4; ++c)
      in_range = in_range && q.position[c] >= 0 && size_t(q.position[c]) < n_positions &&
                 q.uv[c] >= 0 && size_t(q.uv[c]) < n_uvs;
    if (!in_range) continue;
    Imath::V3f p[4];
    for (int c = 0; c < 4; ++c) {
      p[c] = mesh.positions_world[q.position[c]];
      const Imath::V2f& uv = mesh.uvs[q.uv[c]];
      for (int a = 0; a < 3; ++a)
        lo[a] = std::min(lo[a], p[c][a]), hi[a] = std::max(hi[a], p[c][a]);
      for (int a = 0; a < 2; ++a)
        uv_lo[a] = std::min(uv_lo[a], uv[a]), uv_hi[a] = std::max(uv_hi[a], uv[a]);
      for (int a = 0; a < 3; ++a) centre[a] += 0.25 * double(p[c][a]);
    }
    const Imath::V3d d0(p[2] - p[0]), d1(p[3] - p[1]);
    s.area_world += 0.5 * d0.cross(d1).length();
    ++counted;
  }
  if (counted == 0) return s;
  s.bounds_min_world = lo;
  s.bounds_max_world = hi;
  s.uv_min = uv_lo;
  s.uv_max = uv_hi;
  s.mean_centre_world =
      Imath::V3f(float(centre[0] / double(counted)), float(centre[1] / double(counted)),
                 float(centre[2] / double(counted)));
  return s;
}

}  // namespace clothbake
