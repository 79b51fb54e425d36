#pragma once
#include <cstdint>
#include <map>
#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"
#include "rayspace/frame/frame_args.h"

#include <nlohmann/json.hpp>

namespace rayspace::verify {
class BufferSet;
}
namespace rayspace {
struct Scene;
}

namespace rayspace::app {

// The frame, tracer and device options shared with render (FrameArgs), and diff's own.
struct DiffArgs : FrameArgs {
  DiffArgs() { model = KernelModelArgs::Checked(); }  // a verification run checks the workgroups (3% slower)
  std::string scene, report, inject, save_inputs, junit;
  std::vector<std::string> inject_each;  // --inject-each: a frame per fault on one device
  int local_size = 64;
  std::string compare = "auto";  // --compare: auto, bitwise or relaxed
  std::string path = "passes";   // --path: passes (traverse then reduce) or fused (traverse.compact)
  bool progress = false;         // --progress: also when stderr is not a terminal
  bool no_impact = false;        // --no-impact: a divergence's effect on the picture not measured
  std::string backends = "emu,vulkan";  // --backends: emu,vulkan or emu,sim
  bool backends_given = false;
  std::uint32_t subgroup_size = 0;      // --subgroup-size: the simulated GPU's (0: 8)
  std::string sim_checks;               // --sim-checks: the simulated GPU's checkers ("": all)
  std::string device_model;             // --device-model: the simulated GPU's arithmetic ("": lavapipe)
  std::string subgroup_layout;          // --subgroup-layout: how it fills its subgroups ("": linear)
  std::uint64_t step_limit = 0;         // --step-limit: lane-instructions of a simulated workgroup before a hang (0: 2^34)
  bool coverage_options = false;        // --coverage-options: probe the options that reach a user kernel's unreached lines
};

// Runs the whole frame with every pass on both backends (same inputs: the GPU's previous outputs)
// and compares every output bitwise. Returns kOk when all are equal, kDivergence when a pass diverges.
// With --inject-each, a frame per fault on the one device, the report's "faults" holding each frame's
// report: kWorkgroupFault when the checker stopped any frame, else kDivergence when any diverged.
ExitCode RunDiff(const DiffArgs& args);

// RunDiff's work without its report file: the verdict and the report as a value. `on_scene`, when
// given, runs once the scene is loaded and before any frame (RunDiff opens its report file there).
struct DiffResult {
  ExitCode verdict = ExitCode::kOk;
  nlohmann::json report;
};
DiffResult DiffToReport(const DiffArgs& args, const std::function<void(const Scene&)>& on_scene = {});

struct ReplayArgs {
  std::string dir, report, inject;
  KernelModelArgs model = KernelModelArgs::Checked();  // --schedule, --check-workgroups
  int device = -1;
  std::map<std::string, std::uint64_t> device_lacks;  // --device-lacks (test use)
  int local_size = 64;
  KernelFiles kernels;
  std::size_t split_bytes = 0;  // TestLimits, as for render and diff
  std::uint32_t max_groups = 0;
  std::string compare = "auto";  // --compare, as for diff
  std::string backends = "emu,vulkan";  // --backends, as for diff
  bool backends_given = false;
  // The options given on the command line ("--split-bytes", ...); the others come from the recording
  // beside the saved call (diff --save-inputs), so that the call runs as the diff ran it.
  std::set<std::string> given;
  // --strict-math as given or recorded: the kernels are made with it.
  bool strict_math = false;
};

// Runs one saved pass call (diff --save-inputs) on both backends, with the options recorded beside it
// unless given, and compares. Returns kOk when equal, kDivergence when divergent, kNotReproduced when
// the comparison recorded at save time is not reproduced (also when a recorded divergence is now gone).
ExitCode RunReplay(const ReplayArgs& args);

// Throws InputError, naming the file in `dir`, when a saved call's inputs are none a render could have
// made (triangles beyond the coordinate domain, a frame that is not finite or does not match the scene).
void CheckSavedInputs(const verify::BufferSet& in, const std::string& dir);

}  // namespace rayspace::app
