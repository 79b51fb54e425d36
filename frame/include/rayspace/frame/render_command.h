#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/exit_codes.h"
#include "rayspace/frame/frame_args.h"

namespace rayspace::app {

// The frame, tracer and device options shared with diff (FrameArgs), and render's own.
struct RenderArgs : FrameArgs {
  std::string scene, out, stats, direct = "auto", backend = "emu";
  std::string path = "auto";  // --path: auto (fused unless the emulated workgroups are checked), fused or passes
  // --backend sim: the simulated GPU's subgroup size (0: 8), checkers, arithmetic and subgroup layout
  std::uint32_t subgroup_size = 0;
  std::string sim_checks, device_model, subgroup_layout;
  std::uint64_t step_limit = 0;  // lane-instructions of a simulated workgroup before a hang (0: 2^34)
  int threads = 0;
  bool no_oracle = false, progress = false, timings = false;
};

// Runs `rayspace render`: kOk, or kOracleMismatch when the oracle found rays the frame got wrong.
ExitCode RunRender(const RenderArgs& args);

// RunRender's work without its files: the frame, its verdict (kOk, or kOracleMismatch when the oracle
// found rays the frame got wrong) and the statistics file's JSON. `on_scene`, when given, runs once
// the scene is loaded and before the frame, and returns the image's path for the statistics (RunRender
// opens its output files there).
struct RenderValue {
  ExitCode verdict = ExitCode::kOk;
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 8-bit sRGB, row by row from the top
  std::string digest;             // the frame's digest (hex), as the summary prints it
  std::size_t oracle_mismatches = 0;
  nlohmann::json statistics;      // what --stats writes
};
RenderValue RenderToValue(const RenderArgs& args, const std::function<std::string(const Scene&)>& on_scene = {});

}  // namespace rayspace::app
