// diff --coverage-options: for the lines of a user's kernel a diff on the simulated GPU never
// reached, the options that reach them. Each probe is one of mutate's diff configurations (the set
// whose passes together run every kernel and its rarer paths), run as `rayspace diff --backends
// emu,sim` with the same kernels on a small frame; a line is credited to the first probe that
// reaches it.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rayspace::app {

struct CoverageProbeArgs {
  std::string scene, data, size = "16x16";
  std::vector<std::string> kernels;  // --kernel PASS=FILE, as given to the diff
  int timeout = 120;                 // seconds per probe
};

// `coverage`: the diff's kernel_coverage (ReportKernelCoverage). Prints, per kernel with unreached
// lines, the probes that reach them and the lines no probe reaches; returns the same as JSON.
nlohmann::json ProbeCoverageOptions(const CoverageProbeArgs& args, const nlohmann::json& coverage);

// "trim.comp:40-42" -> trim.comp:40, :41, :42 ("file:line" each); "trim.comp:7" -> trim.comp:7.
std::vector<std::string> ExpandLineRuns(const std::vector<std::string>& runs);
// The inverse: consecutive lines of one file joined into runs, in the order given.
std::vector<std::string> JoinLineRuns(const std::vector<std::string>& lines);

}  // namespace rayspace::app
