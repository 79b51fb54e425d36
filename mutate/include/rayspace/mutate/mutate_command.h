// `rayspace mutate` (docs/verification.md): mutants of every GLSL kernel, each run through the
// pass-by-pass diff on a small frame (killed: the pass, buffer and element that caught it; survived),
// and equivalent variants of the kernels through spirv-opt recipes, which must diff equal.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct MutateArgs {
  std::string scene = "scenes/cornell-mirrors.json";
  std::vector<std::string> passes;  // only these passes' kernels (and no include files)
  std::vector<std::string> configs;  // only these diff configurations (mutate_runs::Configs)
  std::size_t limit = 30;           // mutants run (0: every one)
  std::string seed = "1";           // a number, a word, or "commit": the binary's commit
  std::string report, junit, data, size = "32x32", work, survivors, only;
  std::string shard = "0/1";  // --shard I/N: the mutants and variants I, I+N, ... of the run's choice
  std::string variants = "2";  // spirv-opt variants run: a count, or "all"
  int timeout = 60;            // seconds per diff before a mutant counts as hung
  int jobs = 1;
  bool list = false;
  bool cases_only = false;  // --cases-only: replay every kernel case with the built-in kernels, no mutants
  // The actual sides every mutant runs on: emu,vulkan (default), emu,sim (the simulated GPU, its
  // checkers on) or emu,vulkan,sim (both, their scores side by side in one report).
  std::string backends = "emu,vulkan";
};

ExitCode RunMutate(const MutateArgs& args);

// `rayspace mutate merge OUT SHARD...`: the reports of `mutate --shard I/N` runs (every shard of one run
// exactly once) merged into OUT, the same bytes one run writes (mutate_shards.h).
struct MutateMergeArgs {
  std::string out, junit;
  std::vector<std::string> shards;
};
ExitCode RunMutateMerge(const MutateMergeArgs& args);

}  // namespace rayspace::app
