// Hand-made pass calls at the boundaries no frame reaches (docs/verification.md, "Kernel cases"):
// degenerate and opposite cones in the build, a direction whose float dot with itself exceeds 1, and
// the colour values next to each rounding step of resolve. `rayspace mutate` replays each on both
// backends, first with the built-in kernels (they must be equal: a difference is an emulator or driver
// finding at a boundary), then for every mutant of a kernel the case's pass runs that the frames left
// alive.
#pragma once
#include <string>
#include <vector>

#include "rayspace/verify/buffer_set.h"

namespace rayspace::mutate {

struct KernelCase {
  std::string name;    // also the directory it is saved in
  std::string pass;    // the pass whose kernel runs it (rayspace/pass_registry.h)
  std::string method;  // the pass method (emu/calls.h kName) the call is for
  std::string why;     // the boundaries it reaches, in one line
  verify::BufferSet call;
};

std::vector<KernelCase> KernelCases();

}  // namespace rayspace::mutate
