#pragma once
#include <map>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct ExportArgs {
  std::string dir, out;
  std::string inject;            // --inject; without it, the fault comparison.json records
  bool inject_given = false;
  std::vector<std::string> kernels;  // --kernel PASS=FILE; without it, the kernels comparison.json records
  bool kernels_given = false;
  int device = -1;
  std::map<std::string, std::uint64_t> device_lacks;  // --device-lacks (test use)
  int local_size = 0;            // 0: as comparison.json records it, else 64
  std::size_t split_bytes = 0;   // 0: as recorded, else the device's binding limit
  std::uint32_t max_groups = 0;  // 0: as recorded, else the device's
};

// Writes a call saved by `diff --save-inputs` (DIR/NNNN-LABEL) as a reproducer that runs without
// rayspace, using only the Vulkan loader: the call's Vulkan work recorded with the built-in kernels
// on a device whose outputs equal the emulator's, the planted fault (if any) set in the exported
// kernel, and a C program that replays it and compares every read-back (export_writer.h). A call
// that cannot be replayed by compute dispatches alone (the raster) is refused by name.
ExitCode RunExport(const ExportArgs& args);

}  // namespace rayspace::app
