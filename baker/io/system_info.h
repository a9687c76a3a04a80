#pragma once
/// Facts about the machine the program runs on.

#include <cstdint>

namespace clothbake::io {

/// Physical memory in bytes (0 if unknown).
uint64_t physical_memory_bytes();

/// The memory budget for one volume: 3/4 of physical memory, so the rest of
/// the program and the system keep room. Falls back to 4 GiB if unknown.
uint64_t default_memory_budget_bytes();

/// The resident memory of this process now, in bytes (0 if unknown).
uint64_t resident_bytes();

/// The most resident memory this process has held so far, in bytes (its
/// high-water mark, from getrusage; 0 if unknown). A report gives it so an
/// estimate can be checked against what the run really took.
uint64_t peak_resident_bytes();

}  // namespace clothbake::io
