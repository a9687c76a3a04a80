#pragma once
/// A cloth mesh: quadrilaterals with UVs, in world space (PAPER.md s.4).

#include <array>
#include <vector>

#include <Imath/ImathVec.h>

namespace clothbake {

struct QuadMesh {
  /// One face: indices of its four corners, in order around the face
  /// (counter-clockwise seen from the front, so the front normal is
  /// (p1 - p0) x (p3 - p0) at corner 0).
  struct Quad {
    std::array<int, 4> position;  ///< into positions_world
    std::array<int, 4> uv;        ///< into uvs
  };
  std::vector<Imath::V3f> positions_world;
  std::vector<Imath::V2f> uvs;  ///< texture coordinates; the weave follows them
  std::vector<Quad> quads;
};

}  // namespace clothbake
