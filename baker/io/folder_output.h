#pragma once
/// A folder output written whole (a lookup, a material): every file into the
/// temporary sibling (atomic_file.h, folder_siblings), the manifest last, then
/// swapped in by publish_folder. A failure names the folder the user asked
/// for and leaves it as it was. Both folder writers go through here.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

namespace clothbake::io {

/// Every output folder holds this manifest; a folder without one is not ours.
inline constexpr const char* k_folder_manifest_name = "manifest.json";

/// Refuses, before any work, a destination that the swap could not take or
/// should not: a parent folder that is not writable, a file of that name, or
/// a folder that is not empty and holds no manifest.json (`kind`: "lookup",
/// "material", for the message).
void check_folder_destination(const std::string& dir, const std::string& kind);

/// Refuses a folder output whose parent folder does not exist (the folder is
/// written beside its final name, so the parent must be there); `option`
/// names the command-line option ("-o").
void check_folder_parent(const std::string& dir, const std::string& option);

/// Writes the folder `dir`: checks the destination, refuses a disk with less
/// than `bytes_needed` free, then `fill(temp_dir)` writes every file into the
/// temporary sibling, and the folder is swapped in. An InputError from `fill`
/// becomes "cannot write FILE: ...; nothing under this name was changed",
/// naming `dir`.
void write_folder(const std::string& dir, const std::string& kind, uint64_t bytes_needed,
                  const std::function<void(const std::filesystem::path& temp_dir)>& fill);

/// The bytes of the regular files directly in `dir` (a lookup or material
/// folder as written): what the reports give as bytes_on_disk.
uint64_t folder_bytes(const std::string& dir);

/// A JSON file (pretty, two spaces, a final newline), every write checked.
void write_json_file(const std::string& path, const nlohmann::json& doc);

}  // namespace clothbake::io
