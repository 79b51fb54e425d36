#include "memory_estimate.h"

#include <algorithm>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/layout.h"

namespace rayspace::app {

// Per ray: the ray (64), its watertight setup (52), hash key, order and sort scratch (16), its hit
// (8). Per pixel besides: the surface (80) and the raster targets and depth (32). Rays per pixel:
// the largest batch is the shadow rays (one per light), and reflection and refraction batches of
// the same bounce live beside it. Measured peaks stay below this (docs/performance.md, "Memory").
MemoryEstimate EstimateFrameMemory(int width, int height, std::size_t shadow_slots, std::size_t triangles, std::size_t pair_capacity,
                                   int copies) {
  MemoryEstimate e;
  e.pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  e.rays_per_pixel = std::max<std::size_t>(shadow_slots, 1) + 2;
  constexpr std::size_t kPerRay = sizeof(layout::Ray) + 52 + 16 + 8;
  constexpr std::size_t kPerPixel = sizeof(layout::Surface) + 32;
  e.per_pixel = static_cast<std::size_t>(copies) * (kPerPixel + e.rays_per_pixel * kPerRay);
  // Triangles, normals, info, spheres, object tree, and the loaded scene's positions and normals.
  e.scene = triangles * (sizeof(layout::Triangle) + sizeof(layout::TriangleNormals) + 16 + 16 + 32 + 72);
  e.pairs = static_cast<std::size_t>(copies) * pair_capacity * 16;
  e.total = e.pixels * e.per_pixel + e.scene + e.pairs;
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
          {"scene_bytes", e.scene},     {"pair_bytes", e.pairs},          {"machine_bytes", MachineMemoryBytes()}};
}

}  // namespace rayspace::app
