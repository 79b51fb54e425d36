// The frame's options on a command line: registered once on every command that takes them, writing
// into the frame's configuration (rayspace/frame/frame_args.h), so that the commands cannot drift.
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "rayspace/frame/faithful_args.h"
#include "rayspace/frame/frame_args.h"
#include "rayspace/frame/kernel_model.h"

namespace CLI {
class App;
}

namespace rayspace::app {

// Registers --algo, --lists, --node-order, --subdivision, --levels (alias --depth), --bounces, --objects, --tree-leaf, --tree-big, --reduction, --component-size, --pair-capacity, --size,
// --data, --device, --split-bytes, --max-groups, --kernel, --schedule, --check-workgroups and the
// thesis's switches (faithful_args.h) on
// `command`, writing into `args`.
void AddFrameOptions(CLI::App& command, FrameArgs& args);
// --device and --device-lacks (replay runs on a device but renders no frame).
void AddDeviceOption(CLI::App& command, int& device, std::map<std::string, std::uint64_t>& lacks);
// --device-lacks NAME[=VALUE] (test use), parsed into `out` (Settings::device_lacks; rayspace devices too).
void AddDeviceLacksOption(CLI::App& command, std::map<std::string, std::uint64_t>& out);
// --kernel PASS=FILE, repeatable (render --backend vulkan, diff, replay).
void AddKernelOption(CLI::App& command, KernelFiles& kernels);
// --split-bytes and --max-groups (TestLimits): render, diff and replay.
void AddLimitOptions(CLI::App& command, std::size_t& split_bytes, std::uint32_t& max_groups);
// --local-size (diff and replay).
void AddLocalSizeOption(CLI::App& command, int& local_size);

// --schedule and --check-workgroups.
void AddKernelModelOptions(CLI::App& command, KernelModelArgs& args);

// Registers --faithful, --hash-order, --hash-bits, --shadow-rule, --shadow-bounces, --one-object,
// --cone-test, --leaf-test and --child-merge on `command`, writing into `args`. --faithful is resolved
// when the command's parse completes: each switch of the preset that the command line does not give
// is set as if it had been given, so an explicit switch wins over the preset.
void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args);
// The switches of a preset, as `--faithful name` alone on a command line gives them (for callers
// without a command line, such as `rayspace reproduce`). Throws InputError for an unknown name.
FaithfulArgs FaithfulFromPreset(const std::string& name);
// Faithful switches given as command-line words (--cone-test printed ...), on top of rayspace's defaults.
FaithfulArgs FaithfulFromWords(const std::vector<std::string>& words);

}  // namespace rayspace::app
