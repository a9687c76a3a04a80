// Fuzz target: a scene file (io/scene_json.h), as `clothbake render` reads it.
// Its mesh and cloth-spec paths resolve against tests/fuzz/files/.

#include "core/util/error.h"
#include "fuzz_input.h"
#include "io/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)clothbake::io::scene_from_text(clothbake::fuzz::as_text(data, size),
                                         clothbake::fuzz::fixture_path("scene.json"));
  } catch (const clothbake::InputError&) {
  }
  return 0;
}
