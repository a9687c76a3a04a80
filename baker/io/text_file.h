#pragma once
/// Whole files as text, for readers that parse from memory (so the fuzz
/// targets in tests/fuzz/ run the same parse functions without files).

#include <string>

namespace clothbake::io {

/// The contents of a file as bytes. Throws InputError naming the file if it is
/// missing, unreadable or not a regular file (a folder, a device such as
/// /dev/zero that would never end).
std::string read_text_file(const std::string& path);

}  // namespace clothbake::io
