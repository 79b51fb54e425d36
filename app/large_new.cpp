// The executable's operator new: allocations of at least kLargeBytes in huge pages
// (rayspace/large_memory.h). Most of a frame's arrays are std::vectors, filled once, so their pages
// are first touched by the pass that fills them; in huge pages a frame takes about a third of the
// faults. Both paths are the C heap, so every operator delete is free(). The library does not
// replace operator new: a program that links it chooses its own.
#include <cstdlib>
#include <new>

#include "rayspace/large_memory.h"

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

void* operator new(std::size_t bytes) {
  for (;;) {
    void* p = bytes >= rayspace::kLargeBytes ? rayspace::TryAllocateLarge(bytes) : std::malloc(bytes ? bytes : 1);
    if (p) return p;
    std::new_handler h = std::get_new_handler();
    if (!h) throw std::bad_alloc();
    h();
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

#endif
