// Writes a recorded pass call (export_recording.h) as a reproducer that needs only the Vulkan loader:
// repro.c, sequence.txt (its steps, the format at the top of repro.c), kernels/*.spv, inputs/*.bin
// (what the host writes), expected/*.bin (what each read-back must give), call.json and README.md.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "rayspace/export/export_recording.h"

namespace rayspace::app {

// The call and how it was recorded, for the reproducer's README and call.json.
struct ExportInfo {
  std::string saved;             // the saved call's directory, as given
  std::string label;             // its name, NNNN-LABEL
  std::string pass, method;      // its kernel pass and pass method
  std::string device, driver;    // where the sequence was recorded
  std::string inject;            // the planted fault, as diff --inject gave it (empty: none)
  std::map<std::string, std::uint32_t> faults;  // planted kernel faults by pass, set in the exported pipelines
  std::vector<std::string> kernel_files;        // --kernel PASS=FILE, as given or recorded
  std::map<std::string, std::vector<std::uint32_t>> kernels;  // their SPIR-V by pass, exported in place of the built-in
  std::uint32_t local_size = 64;
  bool strict_math = false;
  std::size_t split_bytes = 0;   // --split-bytes (0: the device's binding limit)
  std::uint32_t max_groups = 0;  // --max-groups (0: the device's)
};

// What was written, for the command's summary.
struct ExportCounts {
  std::size_t pipelines = 0, buffers = 0, writes = 0, dispatches = 0, submits = 0, reads = 0, output_reads = 0;
  std::string kernels;  // "trim (planted fault 1), reduce (your kernel my_reduce.comp), ..."
  bool fault_set = false;  // a planted fault is set in one of the exported pipelines
  std::size_t own_kernels = 0;  // pipelines exported with a user's kernel
};

// Writes into `dir`, which must exist and be empty.
ExportCounts WriteExport(const std::filesystem::path& dir, const Recording& rec, const ExportInfo& info);

}  // namespace rayspace::app
