#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "exit_codes.h"
#include "frame_args.h"

namespace rayspace::app {

// The frame, tracer and device options shared with diff (FrameArgs), and render's own.
struct RenderArgs : FrameArgs {
  std::string scene, out, stats, direct = "auto", backend = "emu";
  std::string path = "auto";  // --path: auto (fused unless the emulated workgroups are checked), fused or passes
  // --backend sim: the simulated GPU's subgroup size (0: 8), checkers, arithmetic and subgroup layout
  std::uint32_t subgroup_size = 0;
  std::string sim_checks, device_model, subgroup_layout;
  int threads = 0;
  bool no_oracle = false, progress = false, timings = false;
};

// Runs `rayspace render`: kOk, or kOracleMismatch when the oracle found rays the frame got wrong.
ExitCode RunRender(const RenderArgs& args);

}  // namespace rayspace::app
