#pragma once
/// The `--memory-gib G` option of the commands that refuse work too large
/// for memory (render, lookup-render, bake, volume): G > 0 replaces the
/// default budget (3/4 of physical memory). Bounded to 1 PiB so the
/// conversion to bytes cannot overflow a uint64_t.

#include <cstdint>

#include <CLI/CLI.hpp>

#include "cli/option_range.h"
#include "io/system_info.h"

namespace clothbake::cli {

inline constexpr double kMaxMemoryGib = double(1u << 20);  // 1 PiB

inline void add_memory_option(CLI::App* cmd, double& memory_gib) {
  cmd->add_option("--memory-gib", memory_gib,
                  "memory budget in GiB (default: 3/4 of physical memory)")
      ->check(in_range(0.0, kMaxMemoryGib));
}

inline uint64_t memory_budget_bytes(double memory_gib) {
  return memory_gib > 0.0 && memory_gib <= kMaxMemoryGib ? uint64_t(memory_gib * double(1ull << 30))
                                                         : io::default_memory_budget_bytes();
}

}  // namespace clothbake::cli
