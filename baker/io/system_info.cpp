#include "io/system_info.h"

#include <sys/resource.h>
#include <unistd.h>

#include <fstream>

namespace clothbake::io {

uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : 0;
}

uint64_t default_memory_budget_bytes() {
  const uint64_t phys = physical_memory_bytes();
  return phys ? phys / 4 * 3 : (uint64_t(4) << 30);
}

uint64_t resident_bytes() {
  // statm's second field: resident pages.
  std::ifstream statm("/proc/self/statm");
  uint64_t size = 0, pages = 0;
  if (!(statm >> size >> pages)) return 0;
  const long page = ::sysconf(_SC_PAGESIZE);
  return page > 0 ? pages * uint64_t(page) : 0;
}

uint64_t peak_resident_bytes() {
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return uint64_t(usage.ru_maxrss) * 1024;  // Linux counts it in KiB
}

}  // namespace clothbake::io
