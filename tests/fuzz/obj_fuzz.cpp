// Fuzz target: an OBJ quad mesh (io/obj_reader.h), as a scene's "mesh" is read.

#include "core/util/error.h"
#include "fuzz_input.h"
#include "io/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)clothbake::io::obj_quads_from_text(clothbake::fuzz::as_text(data, size),
                                             clothbake::fuzz::fixture_path("mesh.obj"));
  } catch (const clothbake::InputError&) {
  }
  return 0;
}
