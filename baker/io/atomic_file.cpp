#include "io/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include <fcntl.h>
#include <unistd.h>

#include "core/util/error.h"

namespace clothbake::io {

namespace fs = std::filesystem;

namespace {

/// Every unfinished output of the process. Never destroyed: the interrupt
/// thread may use it while static destructors run.
struct Registry {
  std::mutex mutex;
  std::vector<std::string> paths;
};

Registry& registry() {
  static Registry* r = new Registry;
  return *r;
}

void erase_path(std::vector<std::string>& paths, const std::string& p) {
  const auto it = std::find(paths.begin(), paths.end(), p);
  if (it != paths.end()) paths.erase(it);
}

/// Seconds to wait before publishing (CLOTHBAKE_TEST_HOLD_UNFINISHED), 0 if unset.
double hold_seconds() {
  const char* s = std::getenv("CLOTHBAKE_TEST_HOLD_UNFINISHED");
  if (s == nullptr) return 0.0;
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  return end != s && v > 0.0 ? std::min(v, 600.0) : 0.0;
}

/// Publishes `outputs` together: one lock, one set of renames.
void publish_together(const std::vector<UnfinishedOutput*>& outputs,
                      const std::function<void()>& rename_into_place) {
  if (const double s = hold_seconds(); s > 0.0) {
    for (const UnfinishedOutput* o : outputs)
      std::fprintf(stderr, "clothbake: holding unfinished %s for %g s before publishing\n",
                   o->path().c_str(), s);
    std::this_thread::sleep_for(std::chrono::duration<double>(s));
  }
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  rename_into_place();  // on a throw, each destructor removes its temporary
  for (UnfinishedOutput* o : outputs) erase_path(r.paths, o->path());
}

}  // namespace

UnfinishedOutput::UnfinishedOutput(std::string temp_path) : m_temp_path(std::move(temp_path)) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.paths.push_back(m_temp_path);
}

UnfinishedOutput::~UnfinishedOutput() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  const bool pending = std::find(r.paths.begin(), r.paths.end(), m_temp_path) != r.paths.end();
  if (!pending) return;  // published (renamed away)
  std::error_code ec;
  fs::remove_all(m_temp_path, ec);
  erase_path(r.paths, m_temp_path);
}

void UnfinishedOutput::publish(const std::function<void()>& rename_into_place) {
  publish_together({this}, rename_into_place);
}

int remove_unfinished_outputs_and_freeze() {
  Registry& r = registry();
  r.mutex.lock();  // never unlocked: the process exits next
  int removed = 0;
  for (const std::string& p : r.paths) {
    // A writer may still be creating files in a temporary folder: try again.
    std::error_code ec;
    for (int attempt = 0; attempt < 3; ++attempt) {
      fs::remove_all(p, ec);
      if (!fs::exists(fs::symlink_status(p, ec))) break;
    }
    ++removed;
  }
  return removed;
}

std::string temporary_sibling(const std::string& final_path) {
  static std::atomic<unsigned> counter{0};
  const fs::path final_p(final_path);
  const fs::path dir = final_p.has_parent_path() ? final_p.parent_path() : fs::path(".");
  return (dir / ("." + final_p.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                 std::to_string(counter++) + final_p.extension().string()))
      .string();
}

void write_bytes_checked(const std::string& temp_path, const std::string& final_path,
                         const void* bytes, size_t size) {
  auto fail = [&](const char* what) {
    throw InputError("", std::string(what) + ": " + std::strerror(errno), final_path);
  };
  const int fd = ::open(temp_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create the file");
  const char* p = static_cast<const char*>(bytes);
  size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      const int saved = errno;
      ::close(fd);
      errno = saved;
      fail("cannot write the file");
    }
    p += n;
    left -= size_t(n);
  }
  if (::close(fd) != 0) fail("cannot write the file");
}

void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temp_path)>& write) {
  write_all_atomically({{final_path, write}});
}

void write_all_atomically(
    const std::vector<std::pair<std::string, std::function<void(const std::string&)>>>& files) {
  // Step 1: every file under its temporary name; a throw removes them all.
  std::vector<std::unique_ptr<UnfinishedOutput>> temps;
  std::vector<UnfinishedOutput*> raw;
  for (const auto& [final_path, write] : files) {
    temps.push_back(std::make_unique<UnfinishedOutput>(temporary_sibling(final_path)));
    raw.push_back(temps.back().get());
    write(temps.back()->path());
  }
  // Step 2: all renamed into place at once.
  publish_together(raw, [&] {
    for (size_t i = 0; i < files.size(); ++i) {
      std::error_code ec;
      fs::rename(temps[i]->path(), files[i].first, ec);
      if (ec)
        throw InputError("", "cannot move the finished file into place: " + ec.message(),
                         files[i].first);
    }
  });
}

void check_output_folder(const std::string& final_path, const std::string& option) {
  const fs::path p(final_path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::exists(dir, ec))
    throw InputError(option, "the folder " + dir.string() + " does not exist", final_path);
  if (!fs::is_directory(dir, ec))
    throw InputError(option, dir.string() + " is not a folder", final_path);
  if (fs::is_directory(p, ec))
    throw InputError(option, "is a folder; expected a file name", final_path);
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError(option,
                     "cannot write in the folder " + dir.string() + ": " + std::strerror(errno),
                     final_path);
}

void ensure_directory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw InputError("", "exists and is not a folder", dir);
    return;
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError("", "cannot create the output folder: " + ec.message(), dir);
}

FolderSiblings folder_siblings(const std::string& dir) {
  fs::path final_dir(dir);
  if (!final_dir.has_filename()) final_dir = final_dir.parent_path();  // "out/" -> "out"
  if (final_dir.empty()) throw InputError("", "empty output folder name", dir);
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  const std::string pid = std::to_string(::getpid());
  const std::string name = final_dir.filename().string();
  return {final_dir.string(), (parent / (name + k_folder_temp_tag + pid)).string(),
          (parent / (name + k_folder_old_tag + pid)).string()};
}

void publish_folder(UnfinishedOutput& unfinished, const FolderSiblings& names,
                    const std::string& what) {
  const fs::path final_dir(names.final_dir), temp_dir(names.temp_dir), old_dir(names.old_dir);
  unfinished.publish([&] {
    std::error_code ec;
    const bool had_old = fs::exists(final_dir, ec);
    if (had_old && ::renameat2(AT_FDCWD, temp_dir.c_str(), AT_FDCWD, final_dir.c_str(),
                               RENAME_EXCHANGE) == 0) {
      fs::remove_all(temp_dir, ec);  // now the previous folder
      return;
    }
    if (had_old) {
      fs::remove_all(old_dir, ec);
      fs::rename(final_dir, old_dir, ec);
      if (ec)
        throw InputError("", "cannot move the previous " + what + " aside: " + ec.message(),
                         names.final_dir);
    }
    fs::rename(temp_dir, final_dir, ec);
    if (ec) {
      const std::string why = ec.message();
      if (had_old) fs::rename(old_dir, final_dir, ec);
      throw InputError("", "cannot move the finished " + what + " into place: " + why,
                       names.final_dir);
    }
    if (had_old) fs::remove_all(old_dir, ec);
  });
}

}  // namespace clothbake::io
