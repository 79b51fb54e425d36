// Large arrays in huge pages. A frame writes hundreds of megabytes of fresh arrays (levels' pairs,
// scans, per-ray state), and on a virtual machine the first touch of each 4 KiB page is a fault of
// several microseconds: about a fifth of a frame's CPU. Memory of at least kLargeBytes is aligned
// to 2 MiB and advised as huge pages (MADV_HUGEPAGE), so one fault maps 2 MiB where the system
// grants transparent huge pages ("madvise" or "always"); elsewhere it is ordinary memory.
#pragma once
#include <cstddef>

namespace rayspace {

inline constexpr std::size_t kLargeBytes = std::size_t{2} << 20;

// `bytes` (at least kLargeBytes) from the C heap, aligned to kLargeBytes and advised as huge pages;
// free() or FreeLarge releases it. TryAllocateLarge gives null when the heap has no room,
// AllocateLarge throws std::bad_alloc.
void* TryAllocateLarge(std::size_t bytes) noexcept;
void* AllocateLarge(std::size_t bytes);
void FreeLarge(void* p) noexcept;

}  // namespace rayspace
