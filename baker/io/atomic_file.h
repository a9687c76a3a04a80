#pragma once
/// Write-then-rename: the only way clothbake creates an output file.

#include <functional>
#include <string>

namespace clothbake::io {

/// Calls `write(temp_path)` with a temporary path in the same folder as
/// `final_path` (same file system, so rename is atomic), then renames it to
/// `final_path`. If `write` throws, the temporary file is removed and the
/// exception propagates; `final_path` is never half-written.
/// `temp_suffix_ext` keeps the extension so format-by-extension writers work.
void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temp_path)>& write);

/// Creates `dir` (and parents) if missing; throws InputError naming it if it
/// cannot be created or is not a directory.
void ensure_directory(const std::string& dir);

}  // namespace clothbake::io
