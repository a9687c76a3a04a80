#pragma once
/// Whole files as text, for readers that parse from memory (so the fuzz
/// targets in tests/fuzz/ run the same parse functions without files).

#include <string>

namespace clothbake::io {

/// The contents of a file as bytes. `expected` names what the file should be
/// ("a JSON file", "an OBJ file"), for the message about a folder. Throws
/// InputError naming the file if it is a folder ("is a folder, expected
/// EXPECTED"), missing or unreadable ("cannot open file (missing or
/// unreadable): " and the system's reason) or otherwise not a regular file (a
/// device such as /dev/zero that would never end).
std::string read_text_file(const std::string& path, const std::string& expected);

}  // namespace clothbake::io
