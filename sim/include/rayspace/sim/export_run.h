// Runs a reproducer directory written by `rayspace export` (sequence.txt, kernels/, inputs/,
// expected/: docs/export.md) on the simulator instead of a Vulkan device, and compares every
// read-back with the expected bytes, as the exported repro.c does on a driver.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/sim/executor.h"

namespace rayspace::sim {

struct ReadBackResult {
  std::string file, label;
  bool equal = true;
  std::string mismatch;  // the first differing word, when not equal
};

// Per kernel: its preparation (spirv-val, spirv-opt, decoding) and its execution, timed apart.
struct KernelTiming {
  std::string kernel;
  std::uint64_t dispatches = 0, lane_instructions = 0;
  double prepare_s = 0, run_s = 0;
};

struct ExportRun {
  std::string call;                   // the exported call's name (sequence.txt's header)
  std::vector<ReadBackResult> reads;
  std::uint64_t dispatches = 0;
  ExecStats stats;
  std::vector<KernelTiming> kernels;  // in order of first use
  bool Equal() const;
};

// Runs it on a simulated device of `device`'s shape (lavapipe's subgroup size of 8 recorded the
// expected read-backs). Throws InputError for a directory that is not an export (naming the file and
// line) or a kernel the simulator cannot take; SimError for a fault the kernel commits while it runs.
ExportRun RunExport(const std::string& dir, const DeviceConfig& device);

}  // namespace rayspace::sim
