// A frame's peak memory, estimated before anything is allocated, so that a size the machine cannot
// hold is refused with the estimate instead of failing (or swapping) halfway (docs/performance.md,
// "Memory").
#pragma once
#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace rayspace::app {

struct MemoryEstimate {
  std::size_t pixels = 0, rays_per_pixel = 0;
  std::size_t per_pixel = 0;  // bytes per pixel, over every buffer that grows with the image
  std::size_t scene = 0;      // the triangles and their derived arrays
  std::size_t pairs = 0;      // one traversal level's pairs at the pair capacity
  std::size_t total = 0;
};

// backends: 1 for render, 2 for diff (both sides hold the frame's buffers).
MemoryEstimate EstimateFrameMemory(int width, int height, std::size_t lights, std::size_t triangles, std::size_t pair_capacity,
                                   int backends);
// The machine's physical memory in bytes (0 when unknown).
std::size_t MachineMemoryBytes();
// Refuses (InputError naming --size) a frame whose estimate exceeds the machine's memory.
void CheckFitsMachine(const MemoryEstimate& e, int width, int height);
nlohmann::json MemoryEstimateJson(const MemoryEstimate& e);

}  // namespace rayspace::app
