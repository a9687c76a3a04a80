#pragma once
/// Reads a Wavefront OBJ file as a quad mesh with UVs (PAPER.md s.4: objects
/// are made of quadrilaterals, each carrying the volume texture through its
/// texture coordinates).
///
/// Statements read: `v x y z` (a fourth weight or trailing vertex colours are
/// ignored), `vt u v` (a third coordinate is ignored), `f` with exactly four
/// corners `p/t` or `p/t/n`; indices are 1-based, negative ones count back
/// from the last element defined so far. Ignored: `vn`, `o`, `g`, `s`,
/// `usemtl`, `mtllib` and comments. Anything else is refused, as is a face
/// without texture coordinates (the weave follows the UVs).

#include <string>
#include <string_view>

#include "core/geometry/quad_mesh.h"

namespace clothbake::io {

/// Loads `path`. Throws InputError naming the file and, for content errors,
/// the line ("line 12") for: a missing or unreadable file, malformed or
/// non-finite numbers, indices out of range, faces that are not quads or
/// have no UVs, quads of zero area (area below 1e-12 of the squared diagonal
/// of the mesh's bounding box) or of zero UV area, and a mesh without faces.
QuadMesh read_obj_quads(const std::string& path);

/// read_obj_quads of `text`, the content of `path` (which errors name).
QuadMesh obj_quads_from_text(std::string_view text, const std::string& path);

}  // namespace clothbake::io
