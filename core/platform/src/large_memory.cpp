#include "rayspace/large_memory.h"

#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rayspace {

void* TryAllocateLarge(std::size_t bytes) noexcept {
  // Whole huge pages, so that the advice covers every byte and no neighbour shares the last one.
  if (bytes > SIZE_MAX - kLargeBytes) return nullptr;
  const std::size_t rounded = (bytes + kLargeBytes - 1) / kLargeBytes * kLargeBytes;
  void* p = std::aligned_alloc(kLargeBytes, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (p) (void)madvise(p, rounded, MADV_HUGEPAGE);  // advice: refused where huge pages are off
#endif
  return p;
}

void* AllocateLarge(std::size_t bytes) {
  void* p = TryAllocateLarge(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

void FreeLarge(void* p) noexcept { std::free(p); }

}  // namespace rayspace
