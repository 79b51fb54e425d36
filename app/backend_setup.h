// Chooses the backend of a run: the emulator, or the Vulkan kernels on a device.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "rayspace/emu/backend.h"

namespace rayspace::app {

struct Backend {
  std::string name = "emu";
  std::string device;                            // the Vulkan device's name, or "host"
  std::size_t max_buffer_bytes = 0;              // maxStorageBufferRange (0: no limit)
  std::shared_ptr<void> owner;                   // keeps the Vulkan device alive
  emu::FramePasses* frame = nullptr;             // nullptr: the emulator
  emu::HierarchyPasses* hierarchy = nullptr;     // nullptr: the emulator
  emu::FramePasses& Frame() const { return frame ? *frame : emu::EmuFramePasses(); }
  std::size_t (*extra_dispatches)(const Backend&) = nullptr;  // split dispatches so far (vulkan)
  emu::HierarchyPasses& Hierarchy() const { return hierarchy ? *hierarchy : emu::EmuHierarchyPasses(); }
};

// Per-pixel and per-ray buffers are bound whole (only the pair streams are split): refuses a frame
// whose largest such buffer exceeds the device's limit, naming the size that would fit.
void CheckFrameFits(const Backend& backend, int width, int height, std::size_t lights);

// name "emu" or "vulkan"; `faults` plants kernel faults (pass -> fault, diff --inject). A bad --device
// or a build without Vulkan is an InputError; a failing driver a runtime_error naming the call.
// split_bytes > 0 lowers the size at which the Vulkan backend splits pair-stream dispatches (tests).
Backend MakeBackend(const std::string& name, int device, int local_size = 64,
                    const std::map<std::string, std::uint32_t>& faults = {}, std::size_t split_bytes = 0);

}  // namespace rayspace::app
