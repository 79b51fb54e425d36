#include "rayspace/parallel.h"

#include <omp.h>

#include <atomic>
#include <exception>
#include <mutex>

#include "rayspace/settings.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace rayspace {
namespace {
// An exception must not leave an OpenMP region (the runtime terminates the process): each iteration
// runs under a catch, the first exception is kept, the remaining iterations are skipped, and the
// exception is rethrown on the calling thread after the loop.
// Each iteration also runs with the caller's settings in force on its worker thread.
class FirstException {
 public:
  FirstException() : settings_(CurrentSettings()) {}
  void Run(const std::function<void(std::size_t)>& fn, std::size_t i) {
    if (failed_.load(std::memory_order_relaxed)) return;
    try {
      SettingsInForce in_force(settings_);
      fn(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);
    }
  }
  void Rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  const Settings& settings_;
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::exception_ptr error_;
};

}  // namespace

int ThreadCount() {
  const int n = CurrentSettings().threads;
  return n > 0 ? n : omp_get_max_threads();
}

void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
  const long long count = static_cast<long long>(n);
  const int threads = ThreadCount();
  if (threads <= 1 || n < 2) {
    for (long long i = 0; i < count; ++i) fn(static_cast<std::size_t>(i));
    return;
  }
  FirstException first;
  const std::size_t chunk_size = CurrentSettings().chunk;
  if (chunk_size == 0) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long long i = 0; i < count; ++i) first.Run(fn, static_cast<std::size_t>(i));
  } else {
    const int chunk = static_cast<int>(chunk_size);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads)
    for (long long i = 0; i < count; ++i) first.Run(fn, static_cast<std::size_t>(i));
  }
  first.Rethrow();
}

void ParallelForDynamic(std::size_t n, std::size_t grain, const std::function<void(std::size_t)>& fn) {
  const int threads = ThreadCount();
  if (CurrentSettings().chunk != 0 || threads <= 1 || n < 2) {
    ParallelFor(n, fn);
    return;
  }
  const long long count = static_cast<long long>(n);
  const int chunk = static_cast<int>(grain == 0 ? 1 : grain);
  FirstException first;
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads)
  for (long long i = 0; i < count; ++i) first.Run(fn, static_cast<std::size_t>(i));
  first.Rethrow();
}

ScopedFtzDaz::ScopedFtzDaz() {
#if defined(__SSE__)
  saved_ = _mm_getcsr();
  _mm_setcsr(saved_ | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
#else
  saved_ = 0;
#endif
}

ScopedFtzDaz::~ScopedFtzDaz() {
#if defined(__SSE__)
  _mm_setcsr(saved_);
#endif
}

void ParallelForFtz(std::size_t n, const std::function<void(std::size_t)>& fn) {
  // The mode is per thread: set it inside each worker, around its share of the work.
  ParallelFor(n, [&](std::size_t i) {
    ScopedFtzDaz ftz;
    fn(i);
  });
}

}  // namespace rayspace
