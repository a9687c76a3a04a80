// Fuzz target: a cloth spec, or a scene naming one (io/cloth_spec_json.h), as
// `clothbake volume` reads it. Paths resolve against tests/fuzz/files/.

#include "core/util/error.h"
#include "fuzz_input.h"
#include "io/cloth_spec_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)clothbake::io::cloth_spec_from_text(clothbake::fuzz::as_text(data, size),
                                              clothbake::fuzz::fixture_path("spec.json"));
  } catch (const clothbake::InputError&) {
  }
  return 0;
}
