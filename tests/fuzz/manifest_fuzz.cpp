// Fuzz target: a bake manifest (io/lookup_io.h), as `clothbake lookup-render`
// and `clothbake merge` read it. The images it names are read from
// tests/fuzz/files/lookup/ (a small bake of testscenes/slab).

#include "core/util/error.h"
#include "fuzz_input.h"
#include "io/lookup_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = clothbake::fuzz::as_text(data, size);
  const std::string dir = clothbake::fuzz::fixture_path("lookup");
  try {
    clothbake::io::LookupInfo info;
    (void)clothbake::io::read_lookup_manifest(text, dir, info);
  } catch (const clothbake::InputError&) {
  }
  try {
    (void)clothbake::io::read_lookup_scene_manifest(text, dir);
  } catch (const clothbake::InputError&) {
  }
  return 0;
}
