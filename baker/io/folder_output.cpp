#include "io/folder_output.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include "core/util/error.h"
#include "io/atomic_file.h"

namespace clothbake::io {

namespace fs = std::filesystem;

void check_folder_destination(const std::string& dir, const std::string& kind) {
  std::error_code ec;
  fs::path final_dir(dir);
  if (!final_dir.has_filename()) final_dir = final_dir.parent_path();  // "out/" -> "out"
  // The swap renames inside the parent: it must be writable (if it exists yet).
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  if (fs::is_directory(parent, ec) && ::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InputError(
        "", "cannot write in the folder " + parent.string() + ": " + std::strerror(errno), dir);
  if (!fs::exists(final_dir, ec)) return;
  if (!fs::is_directory(final_dir, ec)) throw InputError("", "exists and is not a folder", dir);
  // The swap deletes the previous contents: only a folder of ours is replaced.
  if (!fs::is_empty(final_dir, ec) && !fs::exists(final_dir / k_folder_manifest_name, ec))
    throw InputError("", "exists and is not a " + kind + " folder (no manifest.json); not "
                             "replacing it", dir);
}

void check_folder_parent(const std::string& dir, const std::string& option) {
  const fs::path final_dir(folder_siblings(dir).final_dir);
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw InputError(option, "the folder " + parent.string() + " does not exist", dir);
}

void write_folder(const std::string& dir, const std::string& kind, uint64_t bytes_needed,
                  const std::function<void(const fs::path& temp_dir)>& fill) {
  const FolderSiblings names = folder_siblings(dir);
  const fs::path temp_dir(names.temp_dir);
  check_folder_destination(dir, kind);
  std::error_code ec;
  if (bytes_needed > 0) {
    // A disk too small for the files is refused before anything is written.
    const fs::path parent = fs::absolute(fs::path(names.final_dir)).parent_path();
    const fs::space_info space = fs::space(parent, ec);
    if (!ec && space.available < bytes_needed)
      throw InputError("", "needs up to " + std::to_string(bytes_needed >> 20) +
                               " MiB and the disk has " + std::to_string(space.available >> 20) +
                               " MiB free",
                       dir);
  }
  fs::remove_all(temp_dir, ec);                    // left over by a crashed run with our pid
  UnfinishedOutput unfinished(temp_dir.string());  // removed on a throw or an interrupt
  fs::create_directories(temp_dir, ec);
  if (ec)
    throw InputError(
        "", "cannot create the temporary folder " + temp_dir.string() + ": " + ec.message(), dir);
  try {
    fill(temp_dir);
  } catch (const InputError& e) {
    // Name the folder the user asked for, not the temporary one.
    throw InputError("",
                     "cannot write " + fs::path(e.file()).filename().string() + ": " + e.message() +
                         "; nothing under this name was changed",
                     dir);
  }
  // The previous folder survives until the new one is in place.
  publish_folder(unfinished, names, kind);
}

void write_json_file(const std::string& path, const nlohmann::json& doc) {
  errno = 0;
  std::ofstream f(path, std::ios::binary);
  f << doc.dump(2) << "\n";
  f.close();
  if (!f) throw InputError("", errno != 0 ? std::strerror(errno) : "write error", path);
}

uint64_t folder_bytes(const std::string& dir) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

}  // namespace clothbake::io
