#pragma once
// `--shard I/N`: part I (counted from 1) of N, as the farm's array tasks
// number them (docs/guide/farm.md).

#include <cstdio>
#include <string>

#include "core/util/error.h"

namespace clothbake::cli {

struct ShardOption {
  int index = 0;  ///< 0-based
  int count = 1;
};

/// Parses "I/N" with 1 <= I <= N; an empty text is the whole job. Throws
/// InputError naming `flag`.
inline ShardOption parse_shard(const std::string& text, const char* flag) {
  if (text.empty()) return {};
  int i = 0, n = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &i, &n, &tail) != 2 || n < 1 || i < 1 || i > n)
    throw InputError(flag, "expected I/N with 1 <= I <= N (part I of N), got '" + text + "'");
  return {i - 1, n};
}

}  // namespace clothbake::cli
