#pragma once
/// Reads a render scene from JSON (format: docs/formats/scene.md): camera,
/// lights, cloth objects (an OBJ quad mesh plus a cloth spec each),
/// background and render settings.

#include <cstdint>
#include <string>

#include "core/scene/scene.h"
#include "io/system_info.h"

namespace clothbake::io {

/// Loads the scene file `path`. Relative mesh and cloth-spec paths are
/// relative to the scene file's folder. Absent keys keep the defaults of
/// core/scene/scene.h; unknown keys, wrong types, non-finite numbers and values out
/// of range are refused. Throws InputError whose file is the scene and whose
/// field is the full path ("objects[1].thickness_world"); errors inside a
/// referenced OBJ or cloth-spec file keep that file's own name and line or
/// field in the message. Also refuses a camera inside a cloth volume (within
/// thickness_world behind a quad's surface). A texture read from a VDB
/// (an object's "volume") is refused over `memory_budget_bytes` (the
/// command's --memory-gib; by default 3/4 of the machine's memory).
Scene load_scene(const std::string& path,
                 uint64_t memory_budget_bytes = default_memory_budget_bytes());

/// load_scene of `text`, the content of the scene file `path` (which errors
/// name and relative paths start from).
Scene scene_from_text(const std::string& text, const std::string& path,
                      uint64_t memory_budget_bytes = default_memory_budget_bytes());

}  // namespace clothbake::io
