#pragma once
/// Checks across the parts of a scene that no single field shows wrong.

#include <optional>
#include <string>

#include "core/scene/scene.h"

namespace clothbake {

/// A camera inside a cloth object's volume.
struct CameraInCloth {
  int object = -1;         ///< the object
  double distance = 0.0;   ///< from the camera to the surface, world units
  double thickness = 0.0;  ///< the object's thickness_world
};

/// The volume of a quad lies behind its front face, down to thickness_world.
/// A camera there would start its rays inside the cloth, which the renderer
/// does not model; returns the first object it is inside, if any. Each quad's
/// bilinear patch is approximated by the triangles (p0, p1, p2) and
/// (p0, p2, p3).
std::optional<CameraInCloth> camera_inside_cloth(const Scene& scene);

/// The object a user names: the first named `name`, else `name` read as an
/// index below the object count; -1 when neither.
int find_object(const Scene& scene, const std::string& name);

}  // namespace clothbake
