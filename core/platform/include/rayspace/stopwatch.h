#pragma once
// Wall time since construction, in milliseconds: the passes' and frames' timings.
#include <chrono>

namespace rayspace {

class Stopwatch {
 public:
  double Ms() const { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace rayspace
