#include "io/atomic_file.h"

#include <atomic>
#include <filesystem>
#include <system_error>

#include <unistd.h>

#include "core/error.h"

namespace clothbake::io {

namespace fs = std::filesystem;

void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temp_path)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path final_p(final_path);
  const fs::path dir = final_p.has_parent_path() ? final_p.parent_path() : fs::path(".");
  // Hidden name, same folder (so rename is atomic), same extension (so writers
  // that pick the format by extension still work).
  const fs::path temp = dir / ("." + final_p.stem().string() + ".tmp" + std::to_string(::getpid()) +
                               "-" + std::to_string(counter++) + final_p.extension().string());
  try {
    write(temp.string());
  } catch (...) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(temp, final_p, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw InputError("", "cannot move the finished file into place: " + ec.message(), final_path);
  }
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

}  // namespace clothbake::io
