#include "core/geometry/mesh_summary.h"

#include <cmath>

#include <gtest/gtest.h>

namespace clothbake {
namespace {

using Imath::V2f;
using Imath::V3f;

// Two unit squares side by side in z = 0, the second lifted at one corner.
QuadMesh two_quads() {
  QuadMesh m;
  m.positions_world = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0.5f}};
  m.uvs = {{0, 0}, {0.5f, 0}, {0.5f, 1}, {0, 1}, {1, 0}, {1, 1}};
  m.quads = {{{0, 1, 2, 3}, {0, 1, 2, 3}}, {{1, 4, 5, 2}, {1, 4, 5, 2}}};
  return m;
}

// Exact values: bounds and UV bounds of the corners, the mean of the quads'
// corner means, and the areas |(p2 - p0) x (p3 - p1)| / 2 (1 for the flat
// square; for the twisted one the diagonals (1, 1, 0.5) and (-1, 1, 0) give
// |(-0.5, -0.5, 2)| / 2 = sqrt(4.5) / 2).
TEST(MeshSummary, ExactOnTwoQuads) {
  const MeshSummary s = summarize_mesh(two_quads());
  EXPECT_EQ(s.bounds_min_world, V3f(0, 0, 0));
  EXPECT_EQ(s.bounds_max_world, V3f(2, 1, 0.5f));
  EXPECT_EQ(s.uv_min, V2f(0, 0));
  EXPECT_EQ(s.uv_max, V2f(1, 1));
  EXPECT_FLOAT_EQ(s.mean_centre_world.x, (0.5f + 1.5f) / 2);
  EXPECT_FLOAT_EQ(s.mean_centre_world.y, 0.5f);
  EXPECT_FLOAT_EQ(s.mean_centre_world.z, (0.0f + 0.125f) / 2);
  EXPECT_NEAR(s.area_world, 1.0 + std::sqrt(4.5) / 2, 1e-6);
}

// One vertex moved: the summary changes (the add-on's mismatch check relies on it).
TEST(MeshSummary, MovingAVertexChangesIt) {
  QuadMesh m = two_quads();
  const MeshSummary a = summarize_mesh(m);
  m.positions_world[5].z = 0.25f;
  const MeshSummary b = summarize_mesh(m);
  EXPECT_NE(a.mean_centre_world, b.mean_centre_world);
  EXPECT_NE(a.area_world, b.area_world);
}

// Quads with an index out of range are skipped; no quads leave zeros.
TEST(MeshSummary, SkipsOutOfRangeQuadsAndHandlesEmpty) {
  QuadMesh m = two_quads();
  m.quads.push_back({{0, 1, 2, 99}, {0, 1, 2, 3}});
  const MeshSummary a = summarize_mesh(two_quads()), b = summarize_mesh(m);
  EXPECT_EQ(a.mean_centre_world, b.mean_centre_world);
  EXPECT_EQ(a.area_world, b.area_world);
  const MeshSummary e = summarize_mesh(QuadMesh{});
  EXPECT_EQ(e.area_world, 0.0);
  EXPECT_EQ(e.bounds_min_world, V3f(0, 0, 0));
}

}  // namespace
}  // namespace clothbake
