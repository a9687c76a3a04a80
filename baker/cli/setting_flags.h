#pragma once
// The core names a setting in its errors by its field ("texels",
// "light_directions"); the command line names the flag that set it. Each
// command lists its own pairs; an error about anything else (a scene's or
// spec's field) keeps its name.

#include <span>
#include <string>
#include <utility>

#include "core/util/error.h"

namespace clothbake::cli {

using SettingFlag = std::pair<const char*, const char*>;  ///< setting, flag

/// The flag of `setting` in `flags`, or null when it is not a setting.
inline const char* flag_of(std::span<const SettingFlag> flags, const std::string& setting) {
  for (const auto& [name, flag] : flags)
    if (setting == name) return flag;
  return nullptr;
}

/// `e` naming the flag when it names one of `flags`' settings, else as it was.
inline InputError with_flag(std::span<const SettingFlag> flags, const InputError& e) {
  if (const char* flag = flag_of(flags, e.field())) return InputError(flag, e.message(), e.file());
  return e;
}

}  // namespace clothbake::cli
