#pragma once
/// Facts about the machine the program runs on.

#include <cstdint>

namespace clothbake::io {

/// Physical memory in bytes (0 if unknown).
uint64_t physical_memory_bytes();

/// The memory budget for one volume: 3/4 of physical memory, so the rest of
/// the program and the system keep room. Falls back to 4 GiB if unknown.
uint64_t default_memory_budget_bytes();

}  // namespace clothbake::io
