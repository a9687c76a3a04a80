#include "io/system_info.h"

#include <unistd.h>

namespace clothbake::io {

uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : 0;
}

uint64_t default_memory_budget_bytes() {
  const uint64_t phys = physical_memory_bytes();
  return phys ? phys / 4 * 3 : (uint64_t(4) << 30);
}

}  // namespace clothbake::io
