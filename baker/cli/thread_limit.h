#pragma once
/// The `--threads N` option of every command: N > 0 caps oneTBB's worker
/// count for the command's lifetime; 0 leaves all cores.

#include <memory>

#include <tbb/global_control.h>

namespace clothbake::cli {

inline std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               threads);
}

}  // namespace clothbake::cli
