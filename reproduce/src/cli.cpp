// The command line of `rayspace reproduce` and `rayspace reproduce merge`.
#include <CLI/CLI.hpp>

#include "rayspace/reproduce/command.h"

namespace rayspace::reproduce {

std::pair<CLI::App*, CLI::App*> AddReproduceCommand(CLI::App& app, ReproduceArgs& a) {
  CLI::App* rc = app.add_subcommand(
      "reproduce", "Regenerate the papers' tables: every configuration measured in-process, ours beside the published "
                   "numbers with the relations the paper states (docs/reproduce.md)");
  rc->add_option("targets", a.targets, "Targets (default thesis; --list shows them all)");
  rc->add_option("--out", a.out, "Directory of the results and the report (default ./reproduce)");
  rc->add_flag("--quick", a.quick, "128x128 frames (the default): the whole thesis target in well under a minute on 2 cores");
  rc->add_flag("--full", a.full, "512x512 frames, the thesis's size");
  rc->add_option("--jobs", a.jobs, "Configurations run at once, the cores shared among them (default 1)")->check(CLI::Range(1, 1024));
  rc->add_option("--shard", a.shard, "Run only the slice I of N (0 <= I < N) of the configurations; combine the "
                 "directories with `reproduce merge`");
  rc->add_option("--junit", a.junit, "Also write the relation checks as a JUnit XML report to this file: a test case per "
                 "relation and place, failed when it does not hold on ours (docs/library.md)");
  rc->add_flag("--resume", a.resume, "Skip configurations whose result is already in --out");
  rc->add_option("--only", a.only, "Run only the configurations whose name (as --list prints it) matches this regular expression");
  rc->add_option("--data", a.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  rc->add_option("--scenes", a.scenes, "Directory of the scene files (default ./scenes, the repository's)");
  rc->add_flag("--list", a.list, "Print the targets and their configurations, one line each, and exit");
  rc->add_flag("--progress", a.progress, "Print progress on stderr (default when stderr is a terminal)");
  rc->add_flag("--fit", a.fit, "Fit what the paper does not publish (thesis: Sponza's camera and light) by the search "
              "docs/reproduce.md fixes; writes the record and the fitted scene into --out");
  rc->add_option("--fit-protocol", a.fit_protocol, "With --fit: the protocol's ranges and constraint (docs/reproduce.md, \"Fits\"): 1, or 2 (plausible poses; the default)")
      ->check(CLI::Range(1, 2));
  rc->add_flag("--fit-small", a.fit_small, "With --fit: a search of a few frames (test use)")->group("");
  rc->add_option("--size", a.size, "Frame size WxH in place of --quick/--full (test use)")->group("");
  rc->add_option("--stop-after", a.stop_after, "Stop as Ctrl-C does after this many configurations (test use)")
      ->check(CLI::Range(1, 1024))
      ->group("");
  CLI::App* mc = rc->add_subcommand("merge", "Combine the directories of `reproduce --shard` runs into one and write its report");
  mc->add_option("out", a.merge_out, "Directory to write the combined results and report into")->required();
  mc->add_option("dirs", a.merge_dirs, "The shard directories, every shard of one run exactly once")->required();
  mc->add_option("--junit", a.junit, "Also write the merged run's relation checks as a JUnit XML report to this file");
  return {rc, mc};
}

}  // namespace rayspace::reproduce
