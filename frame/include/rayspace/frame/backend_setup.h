// Chooses the backend of a run: the emulator, or the Vulkan kernels on a device.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/emu/backend.h"
#include "rayspace/pass_registry.h"
#include <nlohmann/json.hpp>

#include "rayspace/sim/coverage.h"
#include "rayspace/sim/device.h"

namespace rayspace::app {

struct Backend {
  std::string name = "emu";
  std::string device;                            // the Vulkan device's name, or "host"
  std::size_t max_buffer_bytes = 0;              // bytes one binding holds (0: no limit)
  std::uint32_t subgroup_size = 0;               // the Vulkan device's subgroup size (0: the emulator)
  bool correctly_rounded = true;                 // the device rounds every float operation as the emulator
  bool float64 = true;                           // the grids' build kernels run (shaderFloat64)
  std::shared_ptr<void> owner;                   // keeps the Vulkan device alive
  emu::FramePasses* frame = nullptr;             // nullptr: the emulator
  emu::HierarchyPasses* hierarchy = nullptr;     // nullptr: the emulator
  emu::FramePasses& Frame() const { return frame ? *frame : emu::EmuFramePasses(); }
  std::size_t (*extra_dispatches)(const Backend&) = nullptr;  // split dispatches so far (vulkan)
  std::size_t (*paged_arrays)(const Backend&) = nullptr;      // arrays bound over several pages (vulkan)
  std::size_t (*folded_launches)(const Backend&) = nullptr;   // launches folded into rows of workgroups (vulkan)
  emu::HierarchyPasses& Hierarchy() const { return hierarchy ? *hierarchy : emu::EmuHierarchyPasses(); }
  // Plants other kernel faults between frames and starts the dispatch counts anew (vulkan; diff
  // --inject-each runs a frame per fault on one device).
  void (*set_faults)(const Backend&, const std::map<std::string, std::uint32_t>&) = nullptr;
  // Launches of a pass's kernel so far (vulkan): whether a user's kernel ran.
  std::uint64_t (*launches)(const Backend&, PassId) = nullptr;
  // The lines of a pass's kernel executed so far (sim only; nothing elsewhere).
  std::optional<sim::LineCoverage> (*coverage)(const Backend&, PassId) = nullptr;
};

// --algo grid on a Vulkan device without 64-bit floats (the grids' build bins in double): refused as
// an option this device cannot honour, naming what it lacks.
void CheckGridBuild(const Backend& backend);


// The Vulkan backend splits or pages every buffer that grows with the frame, over at most
// layout::kBufferPages bindings per array: refuses, as bad input, a frame or scene beyond that, naming
// the size that would fit.
// `size_from` names where the size came from (SizeFrom in cli_util.h).
void CheckFrameFits(const Backend& backend, int width, int height, std::size_t shadow_slots, std::size_t triangles,
                    const std::string& size_from = "--size");

// Test hooks: make the Vulkan device look smaller, so that the splitting, paging and launch-folding
// paths run on small frames (0 keeps the device's own limit).
struct TestLimits {
  std::size_t storage_bytes = 0;  // --split-bytes: bytes per storage binding
  std::uint32_t groups_x = 0;     // --max-groups: workgroups per launch row
};

// A user's kernels in place of built-in ones: `--kernel PASS=FILE` (.comp or .spv), each checked
// against the pass's contract (bindings, push constants, workgroup size) by reflection. Every
// refusal (unknown pass, unreadable file, GLSL that does not compile, a contract mismatch) is an
// InputError naming the pass and what is wrong.
struct KernelFiles : std::vector<std::string> {  // "PASS=FILE" as given
  using std::vector<std::string>::vector;
  // Whose GLSL includes a .comp file compiles against: an install's prefix, or empty for the install
  // holding this executable, else the source tree (rayspace/install_paths.h).
  std::filesystem::path data_prefix;
};
// After a frame on the simulated GPU with user kernels (--kernel): prints each one's share of lines
// reached and the runs of lines never reached, which an equal verdict says nothing about. Returns the
// report's "kernel_coverage" (null when there is nothing to report).
nlohmann::json ReportKernelCoverage(const Backend& backend, const KernelFiles& kernels);
// Each kernel read and checked (the refusals above), as SPIR-V by pass; empty without a Vulkan backend.
std::map<std::string, std::vector<std::uint32_t>> LoadKernelFiles(const KernelFiles& kernels);

// After the run: a --kernel whose pass the run never launched is an InputError (exit 2) naming the
// pass, the options under which it runs, and the passes the run launched. A kernel the run does not
// execute is not tested by it, so no verdict of the run may stand for it.
void CheckKernelsRan(const Backend& backend, const KernelFiles& kernels);

// The simulated GPU's configuration from the options that choose it (empty: the defaults, lavapipe's
// arithmetic and layout, every checker). `backends` is diff's list ("emu,sim", ...) or render's one
// backend; an option given where no side is the simulated GPU is an InputError naming it.
sim::DeviceConfig SimulatedConfig(const std::string& backends, std::uint32_t subgroup_size, const std::string& schedule,
                                  const std::string& sim_checks, const std::string& device_model, const std::string& subgroup_layout,
                                  std::uint64_t step_limit = 0);

// name "emu" or "vulkan"; `faults` plants kernel faults (pass -> fault, diff --inject). A bad --device
// or a build without Vulkan is an InputError; a failing driver a runtime_error naming the call.
// `simulated`: the simulated GPU's configuration (name "sim").
Backend MakeBackend(const std::string& name, int device, int local_size = 64,
                    const std::map<std::string, std::uint32_t>& faults = {}, const TestLimits& limits = {},
                    const KernelFiles& kernels = {}, const sim::DeviceConfig& simulated = {});

}  // namespace rayspace::app
