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

// copies: how many copies of the frame's buffers live at once: 1 for render and bench, kDiffCopies
// for diff.
MemoryEstimate EstimateFrameMemory(int width, int height, std::size_t shadow_slots, std::size_t triangles, std::size_t pair_capacity,
                                   int copies);
// diff holds the frame on both backends, and the differ holds each call's encoded inputs and the
// expected side's outputs beside them; the impact of a divergence keeps every batch's rays and hits
// of two further frames, one per side.
inline constexpr int kDiffCopies = 4;
// The machine's physical memory in bytes (0 when unknown).
std::size_t MachineMemoryBytes();
// Refuses (InputError naming `flag` and the size) a frame whose estimate exceeds the machine's memory;
// `subject` says what needs it ("the frame", "the diff").
void CheckFitsMachine(const MemoryEstimate& e, int width, int height, const char* flag = "--size",
                      const char* subject = "the frame");
nlohmann::json MemoryEstimateJson(const MemoryEstimate& e);

}  // namespace rayspace::app
