#include "rayspace/frame/memory_estimate.h"

#include <algorithm>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/layout.h"

namespace rayspace::app {

// Per ray: the ray (64), its watertight setup (52), hash key, order and sort scratch (16), its hit
// (8). Per pixel besides: the surface (80) and the raster targets and depth (32). Rays per pixel:
// the largest batch is the shadow rays (one per light), and reflection and refraction batches of
// the same bounce live beside it. Per triangle (measured with heaptrack on a million small
// triangles): the loaded mesh (72 bytes), the flattened frame arrays (114), the tracer's spheres and
// object-tree index (110), the raster's setup (105) and the frame's triangle spheres (16); per
// object, its few allocations (256). CRSH holds each batch's top nodes (a node above
// subdivision^levels rays) against every object, a byte each; the object tree starts from the same
// product (kTreeRootBytes each). The pass-by-pass path holds one
// traversal call's slots: at the top level at most kMaxTopGrid, and no more than a batch's rays
// (the most top nodes) times its triangles; below, the pairs above (at most the pair capacity) times
// the children of each. The object tree holds its pairs and final pairs (each up to the pair
// capacity, 8 bytes a pair), a round's output and its blocks' parts before they are checked against
// it: kTreeLists lists at the capacity. Measured peaks stay below this (docs/performance.md,
// "Memory").
MemoryEstimate EstimateFrameMemory(const Scene& scene, int width, int height, const MemoryUse& use) {
  constexpr std::size_t kPerTriangle = 72 + 114 + 110 + 105 + 16, kPerObject = 256, kTreeLists = 5;
  // The object tree's first round: every top node against every object's root, as slots (flag, cone
  // and item: 9 bytes), their reduction's indices (4) and the compacted pairs (8).
  constexpr std::size_t kTreeRootBytes = 9 + 4 + 8;
  const std::size_t shadow_slots = ShadowSlotsPerSurface(scene.lights), triangles = scene.TriangleCount();
  const std::size_t pair_capacity = use.pair_capacity;
  MemoryEstimate e;
  const std::size_t copies = static_cast<std::size_t>(std::max(use.copies, 1));
  e.pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  e.rays_per_pixel = std::max<std::size_t>(shadow_slots, 1) + 2;
  constexpr std::size_t kPerRay = sizeof(layout::Ray) + 52 + 16 + 8;
  constexpr std::size_t kPerPixel = sizeof(layout::Surface) + 32;
  e.per_pixel = copies * (kPerPixel + e.rays_per_pixel * kPerRay);
  e.scene = triangles * kPerTriangle + scene.objects.size() * kPerObject;
  const std::size_t batch_rays = e.pixels * std::max<std::size_t>(shadow_slots, 1);
  if (use.object_mask || use.object_tree) {
    const int levels = use.levels > 0 ? use.levels : emu::AutoLevels(batch_rays, std::max(use.subdivision, 2));
    std::size_t below_top = 1;
    for (int l = 0; l < levels && below_top < batch_rays; ++l) below_top *= static_cast<std::size_t>(std::max(use.subdivision, 2));
    const std::size_t top_objects = (batch_rays / below_top + 1) * scene.objects.size();
    e.objects = copies * top_objects * ((use.object_mask ? 1 : 0) + (use.object_tree ? kTreeRootBytes : 0));
  }
  e.pairs = copies * pair_capacity * (use.object_tree ? std::max<std::size_t>(16, kTreeLists * 8) : 16);
  if (use.slot_copies > 0) {
    const std::size_t batch_tris = std::min<std::size_t>(std::max<std::size_t>(triangles, 1), std::size_t{1} << layout::kPairTriangleBits);
    const std::size_t top = batch_rays > emu::kMaxTopGrid / batch_tris ? emu::kMaxTopGrid : batch_rays * batch_tris;
    const std::size_t below = pair_capacity * static_cast<std::size_t>(std::max(use.subdivision, 1));
    e.slots = static_cast<std::size_t>(use.slot_copies) * std::max(top, below) * kSlotBytes;
  }
  e.total = e.pixels * e.per_pixel + e.scene + e.objects + e.pairs + e.slots;
  return e;
}

std::size_t MachineMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
}

void CheckFitsMachine(const MemoryEstimate& e, int width, int height, const char* flag, const char* subject) {
  const std::size_t machine = MachineMemoryBytes();
  if (machine == 0 || e.total <= machine) return;
  ThrowInput("{} {}x{}: {} needs an estimated {:.1f} GB ({} bytes per pixel, {:.1f} GB for the scene), more than this "
             "machine's {:.1f} GB of memory",
             flag, width, height, subject, static_cast<double>(e.total) / 1e9, e.per_pixel, static_cast<double>(e.scene) / 1e9,
             static_cast<double>(machine) / 1e9);
}

nlohmann::json MemoryEstimateJson(const MemoryEstimate& e) {
  return {{"total_bytes", e.total},     {"bytes_per_pixel", e.per_pixel}, {"rays_per_pixel", e.rays_per_pixel},
          {"scene_bytes", e.scene},     {"object_mask_bytes", e.objects}, {"pair_bytes", e.pairs},          {"slot_bytes", e.slots},
          {"machine_bytes", MachineMemoryBytes()}};
}

}  // namespace rayspace::app
