#include "core/scene/scene_checks.h"

#include <utility>

#include "core/geometry/closest_point.h"

namespace clothbake {

std::optional<CameraInCloth> camera_inside_cloth(const Scene& scene) {
  using Imath::V3d;
  auto to_double = [](const Imath::V3f& v) { return V3d(v.x, v.y, v.z); };
  const V3d eye = to_double(scene.camera.position_world);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const ClothObject& object = scene.objects[i];
    const double thickness = object.thickness_world;
    for (const QuadMesh::Quad& quad : object.mesh.quads) {
      V3d p[4];
      for (int c = 0; c < 4; ++c) p[c] = to_double(object.mesh.positions_world[quad.position[c]]);
      for (const auto& [b, c] : {std::pair{1, 2}, std::pair{2, 3}}) {
        const V3d normal = (p[b] - p[0]).cross(p[c] - p[0]);
        if (normal.length() == 0.0) continue;
        const V3d offset = eye - closest_on_triangle(eye, p[0], p[b], p[c]);
        const double distance = offset.length();
        if (distance < thickness && offset.dot(normal) <= 0.0)
          return CameraInCloth{int(i), distance, thickness};
      }
    }
  }
  return std::nullopt;
}

int find_object(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].name == name) return int(i);
  if (!name.empty() && name.size() < 9 && name.find_first_not_of("0123456789") == std::string::npos &&
      std::stoi(name) < int(scene.objects.size()))
    return std::stoi(name);
  return -1;
}

}  // namespace clothbake
