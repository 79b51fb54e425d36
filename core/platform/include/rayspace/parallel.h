// ParallelFor: the one way emulated passes run in parallel. Each element's work must depend only on
// its index and the pass inputs, so the output is the same for every thread count and schedule.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>

namespace rayspace {

// Threads ParallelFor uses: the settings' (rayspace/settings.h), or OpenMP's default. The settings'
// chunk size picks the schedule; each worker runs with the caller's settings in force.
int ThreadCount();

// Runs fn(i) for i in [0, n). Timings and logs are labelled by the pass that calls it.
void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

// ParallelFor for items of uneven cost (the fused path's blocks and pairs): handed out `grain` at a
// time as threads free up, unless the settings chose a chunk size. The output is the same either way.
void ParallelForDynamic(std::size_t n, std::size_t grain, const std::function<void(std::size_t)>& fn);

// Sets the CPU's flush-to-zero and denormals-are-zero modes on the calling thread for the lifetime
// of the object: lavapipe runs its whole draw path (vertex, clip, setup, fragment) in that mode.
class ScopedFtzDaz {
 public:
  ScopedFtzDaz();
  ~ScopedFtzDaz();
  ScopedFtzDaz(const ScopedFtzDaz&) = delete;
  ScopedFtzDaz& operator=(const ScopedFtzDaz&) = delete;

 private:
  unsigned saved_;
};

// ParallelFor whose body runs with FTZ/DAZ set on every worker thread.
void ParallelForFtz(std::size_t n, const std::function<void(std::size_t)>& fn);

}  // namespace rayspace
