// A std::vector whose resize leaves new elements uninitialised: for scratch the lanes write before
// anything reads it (the fused levels' blocks), where zeroing first is a pass over memory that every
// element's own write repeats.
#pragma once
#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "rayspace/large_memory.h"

namespace rayspace::emu {

template <typename T>
struct UninitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitAllocator<U>;
  };
  UninitAllocator() = default;
  template <typename U>
  UninitAllocator(const UninitAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n * sizeof(T) < kLargeBytes) return std::allocator<T>::allocate(n);
    return static_cast<T*>(AllocateLarge(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kLargeBytes) std::allocator<T>::deallocate(p, n);
    else FreeLarge(p);
  }
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};

template <typename T>
using UninitVector = std::vector<T, UninitAllocator<T>>;

// The same elements in the same order, whichever allocator holds them.
template <typename T>
bool operator==(const UninitVector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

}  // namespace rayspace::emu
