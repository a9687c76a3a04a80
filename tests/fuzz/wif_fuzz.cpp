// Fuzz target: a WIF weaving draft (io/wif_reader.h) as `clothbake volume
// FILE.wif` reads it: parsed, turned into a cloth spec and validated, and its
// drawdown computed. Any input must end in a spec or an InputError.

#include "core/util/error.h"
#include "core/weave/loom_draft.h"
#include "fuzz_input.h"
#include "io/cloth_spec_json.h"
#include "io/wif_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const clothbake::io::WifFile wif =
        clothbake::io::parse_wif(clothbake::fuzz::as_text(data, size), "fuzz.wif");
    (void)clothbake::io::cloth_spec_from_wif(wif);
  } catch (const clothbake::InputError&) {
  }
  return 0;
}
