#include "io/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/util/error.h"

namespace clothbake::io {

std::string read_text_file(const std::string& path, const std::string& expected) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError("", "is a folder, expected " + expected, path);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError("",
                     std::string("cannot open file (missing or unreadable): ") +
                         (errno != 0 ? std::strerror(errno) : "open failed"),
                     path);
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("", "is not a regular file", path);
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError("", "read error", path);
  return ss.str();
}

}  // namespace clothbake::io
