#pragma once
#include <cstddef>
#include <string>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct AccuracyArgs {
  std::string scene, data, size = "128x128", out = ".";
  std::size_t samples = 100000;
  double min_time = 0.2;  // seconds each timed pass of a mode runs at the least (--min-time)
  bool end_to_end = true;
};

// Measures, for the cone-sphere test and the ray-triangle test, every precision mode on the scene's
// own workload (queries sampled from a CRSH frame) and on near-boundary variants of it: ns per test,
// false negatives and false positives against the exact answer; and, for the cone-sphere modes, the
// frame time and the rays whose result changes. Writes OUT/<scene>-accuracy.{md,csv,png}.
ExitCode RunAccuracy(const AccuracyArgs& args);

}  // namespace rayspace::app
