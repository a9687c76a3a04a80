#pragma once
/// Write-then-rename: the only way clothbake creates an output file or folder.
/// Every unfinished output (a temporary file or folder beside its final name)
/// is recorded process-wide, so that an interrupt (cli/interrupt.h) can remove
/// them all and leave every final name as it was before the run.

#include <functional>
#include <string>
#include <vector>

namespace clothbake::io {

/// A temporary file or folder that will become a final output. While it
/// lives, `remove_unfinished_outputs()` (the interrupt path) would delete it;
/// the destructor deletes it unless `publish` ran.
class UnfinishedOutput {
 public:
  explicit UnfinishedOutput(std::string temp_path);
  ~UnfinishedOutput();
  UnfinishedOutput(const UnfinishedOutput&) = delete;
  UnfinishedOutput& operator=(const UnfinishedOutput&) = delete;

  const std::string& path() const { return m_temp_path; }

  /// Runs `rename_into_place` (the renames that make the output final) under
  /// the lock the interrupt path takes: an interrupt lands wholly before it
  /// (temporary removed, final names untouched) or wholly after it. If it
  /// throws, the temporary is removed and the exception propagates.
  /// Honours CLOTHBAKE_TEST_HOLD_UNFINISHED (seconds to wait first, for tests
  /// that interrupt a writer at its most delicate point).
  void publish(const std::function<void()>& rename_into_place);

 private:
  std::string m_temp_path;
  bool m_published = false;
};

/// Removes every unfinished output of this process and keeps the registry
/// locked for good, so no publish can follow; returns how many were removed.
/// Only for a process about to exit (the interrupt path).
int remove_unfinished_outputs_and_freeze();

/// A hidden temporary name beside `final_path` (same folder, so rename is
/// atomic; same extension, so writers that pick the format by extension work).
std::string temporary_sibling(const std::string& final_path);

/// Writes `bytes` to `temp_path`, checking every write and the close: a full
/// disk or a file size limit (EFBIG) is an InputError naming `final_path`
/// with the system's reason, never a silently short file.
void write_bytes_checked(const std::string& temp_path, const std::string& final_path,
                         const void* bytes, size_t size);

/// Calls `write(temp_path)` with a temporary path in the same folder as
/// `final_path`, then renames it to `final_path`. If `write` throws, the
/// temporary file is removed and the exception propagates; `final_path` is
/// never half-written.
void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temp_path)>& write);

/// Several files that appear together or not at all (a render's EXR and PNG):
/// each `write(temp_path)` runs in turn; only when all succeeded are they
/// renamed into place, in one publish. Throws InputError naming the file that
/// failed; then no final name has changed.
void write_all_atomically(
    const std::vector<std::pair<std::string, std::function<void(const std::string&)>>>& files);

/// Refuses an output path whose folder does not exist, is not a folder or is
/// not writable, before any work is done (the write itself still reports
/// other failures: a full disk, a quota).
/// `option` names the command-line option ("-o", "--png").
void check_output_folder(const std::string& final_path, const std::string& option);

/// Where a folder output `final_dir` is written before it is swapped in, and
/// where the folder it replaces is set aside meanwhile: siblings named
/// "<name>.tmp-<pid>" and "<name>.old-<pid>" (k_folder_temp_tag,
/// k_folder_old_tag). The Blender add-on tidies up after a bake it killed by
/// the same names (blender_addon/clothbake/core/defaults.py, folder_siblings;
/// tests/addon/test_defaults.py reads these two tags from this header).
inline constexpr const char* k_folder_temp_tag = ".tmp-";
inline constexpr const char* k_folder_old_tag = ".old-";
struct FolderSiblings {
  std::string final_dir, temp_dir, old_dir;
};
/// The names for `dir` ("out/" is taken as "out"); throws InputError for an
/// empty name.
FolderSiblings folder_siblings(const std::string& dir);

/// Swaps a finished folder into place inside `unfinished.publish`: the
/// previous `final_dir` (if any) survives until the new one is there. Where
/// the file system can, one exchange of the two names (not even a kill -9
/// finds the final name missing); else two renames, between which an
/// interrupt cannot fall. Throws InputError naming `final_dir` (which is then
/// as it was).
void publish_folder(UnfinishedOutput& unfinished, const FolderSiblings& names,
                    const std::string& what);

/// Creates `dir` (and parents) if missing; throws InputError naming it if it
/// cannot be created or is not a directory.
void ensure_directory(const std::string& dir);

}  // namespace clothbake::io
