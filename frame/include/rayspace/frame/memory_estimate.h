// A frame's peak memory, estimated before anything is allocated, so that a size the machine cannot
// hold is refused with the estimate instead of failing (or swapping) halfway (docs/performance.md,
// "Memory").
#pragma once
#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/scene.h"

namespace rayspace::app {

struct MemoryEstimate {
  std::size_t pixels = 0, rays_per_pixel = 0;
  std::size_t per_pixel = 0;  // bytes per pixel, over every buffer that grows with the image
  std::size_t scene = 0;      // the triangles and objects and what each pass derives from them
  std::size_t objects = 0;    // one batch's top nodes x objects: CRSH's mask, the object tree's first round
  std::size_t pairs = 0;      // one traversal level's pairs at the pair capacity, or the object tree's lists
  std::size_t slots = 0;      // the pass-by-pass path's slot streams of one traversal call
  std::size_t total = 0;
};

// What a run holds at once.
struct MemoryUse {
  int copies = 1;       // of the frame's buffers and pairs
  int slot_copies = 0;  // of one traversal call's slot streams: 0 on the fused path, which has none
  int subdivision = emu::HierarchyConfig{}.subdivision;  // a lower level's slots: its parents' pairs times these
  std::size_t pair_capacity = emu::HierarchyConfig{}.pair_capacity;  // pairs a level holds
  int levels = emu::HierarchyConfig{}.depth;  // the hierarchy's levels; 0: from the pixels (--levels auto)
  bool object_mask = false;  // CRSH: each batch's top nodes against every object's sphere
  bool object_tree = false;  // --objects tree or auto: the object tree's pair lists may be held
};
// A Vulkan frame: the host's buffers and the device's (lavapipe's device memory is the host's).
inline constexpr int kVulkanCopies = 2;
// diff holds the frame on the emulator and on the device (host and device buffers), and the differ
// holds both sides' outputs of a call (it views the call's inputs; the count is an upper bound kept
// from when it copied them); the impact of a divergence keeps every batch's rays and hits of two
// further frames, one per side. Of a traversal call's slots: the emulator's, the device's as read
// back, and the reduction's decoded inputs (a bound: they are views now).
inline constexpr int kDiffCopies = 5;
inline constexpr int kDiffSlotCopies = 3;
// Bytes a pass-by-pass slot costs the host: its flag and tested count (a byte each) and its value.
inline constexpr std::size_t kSlotBytes = 6;

// A frame of `scene` at width x height: its lights' shadow rays, its triangles.
MemoryEstimate EstimateFrameMemory(const Scene& scene, int width, int height, const MemoryUse& use);
// The machine's physical memory in bytes (0 when unknown).
std::size_t MachineMemoryBytes();
// Refuses (InputError naming `flag` and the size) a frame whose estimate exceeds the machine's memory;
// `subject` says what needs it ("the frame", "the diff").
void CheckFitsMachine(const MemoryEstimate& e, int width, int height, const char* flag = "--size",
                      const char* subject = "the frame");
nlohmann::json MemoryEstimateJson(const MemoryEstimate& e);

}  // namespace rayspace::app
