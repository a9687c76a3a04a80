#pragma once
/// Shared by the fuzz targets: where the files a fuzzed input may name live
/// (a fixed folder of the source tree: tests/fuzz/files/), and the input as
/// text. Each target feeds the bytes to the same parse function the program
/// calls after reading the file, and accepts InputError (a clean refusal);
/// anything else (another exception, a crash, a sanitiser report) is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#ifndef CLOTHBAKE_FUZZ_FILES
#error "CLOTHBAKE_FUZZ_FILES must name tests/fuzz/files (set by tests/fuzz/CMakeLists.txt)"
#endif

namespace clothbake::fuzz {

/// tests/fuzz/files/NAME: relative paths in a fuzzed file resolve there.
inline std::string fixture_path(const char* name) {
  return std::string(CLOTHBAKE_FUZZ_FILES) + "/" + name;
}

inline std::string as_text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace clothbake::fuzz
