#include "core/plane.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <limits>

namespace ssgi {

void AdviseHugePages(void* data, size_t bytes) {
  constexpr size_t kHugePage = size_t(2) << 20;
  if (bytes < kHugePage) return;
  const uintptr_t pageSize = uintptr_t(::sysconf(_SC_PAGESIZE));
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + pageSize - 1) & ~(pageSize - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(pageSize - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

bool RetainFreedMemory(bool retain) {
#if defined(__GLIBC__)
  constexpr int kFreshThreshold = 128 << 10, kRetainThreshold = 32 << 20;
  return ::mallopt(M_MMAP_THRESHOLD, retain ? kRetainThreshold : kFreshThreshold) == 1 &&
         ::mallopt(M_TRIM_THRESHOLD, retain ? std::numeric_limits<int>::max() : kFreshThreshold) == 1;
#else
  return !retain;
#endif
}

}  // namespace ssgi
