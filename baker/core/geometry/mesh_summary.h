#pragma once
/// A few numbers that tell one quad mesh from another with a tolerance: its
/// world bounds, UV bounds, mean quad centre and total area. A lookup records
/// them per object (docs/formats/lookup.md, `objects[o].mesh`) so a reader that
/// cannot recompute clothbake's exact scene hash (the Blender add-on, holding
/// a mesh that went through an OBJ file and back) can still refuse a lookup
/// baked from another mesh, or from this one before it was moved.

#include <Imath/ImathVec.h>

#include "core/geometry/quad_mesh.h"

namespace clothbake {

struct MeshSummary {
  Imath::V3f bounds_min_world{0, 0, 0}, bounds_max_world{0, 0, 0};  ///< of the quads' corners
  Imath::V2f uv_min{0, 0}, uv_max{0, 0};                            ///< of the quads' UVs
  Imath::V3f mean_centre_world{0, 0, 0};  ///< mean over quads of the mean of its 4 corners
  double area_world = 0.0;                ///< sum over quads of |(p2 - p0) x (p3 - p1)| / 2
};

/// The summary of the corners and UVs the quads use (an index out of range is
/// skipped: the scene reader refuses such meshes before this is called).
MeshSummary summarize_mesh(const QuadMesh& mesh);

}  // namespace clothbake
