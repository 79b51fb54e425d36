// `rayspace reproduce`: regenerates the papers' tables beside the published numbers
// (docs/reproduce.md), and `rayspace reproduce merge`, which combines shard directories.
#pragma once
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"
#include "rayspace/reproduce/runner.h"

namespace CLI {
class App;
}

namespace rayspace::reproduce {

struct ReproduceArgs {
  std::vector<std::string> targets;
  std::string out = "reproduce", shard = "0/1", only, data, scenes = "scenes", size, junit;
  bool quick = false, full = false, list = false, resume = false, progress = false, fit = false, fit_small = false;
  int fit_protocol = 0;  // --fit-protocol; 0: not given (the latest, fit_thesis.h)
  int jobs = 1, stop_after = 0;
  std::string merge_out;
  std::vector<std::string> merge_dirs;
};

// Registers `reproduce` and its `merge` subcommand on `app`; returns them.
std::pair<CLI::App*, CLI::App*> AddReproduceCommand(CLI::App& app, ReproduceArgs& args);

ExitCode RunReproduce(const ReproduceArgs& args, const FrameFn& frame);
ExitCode RunMerge(const ReproduceArgs& args);

}  // namespace rayspace::reproduce
