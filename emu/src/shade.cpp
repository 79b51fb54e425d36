// Shading (thesis eq. 3.19) into the fixed-point accumulator. Mirrors gpu/shaders/shade.comp.
#include <atomic>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/shade_math.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

// Converts a contribution to fixed point. Integer sums do not depend on the order of addition.
std::uint64_t ToFixed(float c) {
  const float v = Clamp(c, 0.0f, layout::kAccumMax);
  return static_cast<std::uint64_t>(v * layout::kAccumScale);
}

}  // namespace

void PassShade(const call::Shade& c) {
  const SceneBuffers& scene = *c.scene;
  const In<layout::Surface> surfaces = c.surfaces;
  const In<std::uint32_t> shadow_flags = c.shadow_flags, shadow_offsets = c.shadow_offsets, occluded = c.occluded;
  std::vector<std::uint64_t>& accum = *c.accum;
  const std::size_t slots = ShadowSlots(scene.lights);
  ParallelFor(surfaces.size(), [&](std::size_t s) {
    const layout::Surface& sf = surfaces[s];
    if (sf.position.w == 0.0f) return;
    const glm::vec3 color = ShadeColorOf<float>(scene, sf, [&](std::size_t j) {
      const std::size_t slot = s * slots + j;
      return shadow_flags[slot] && !occluded[shadow_offsets[slot]];
    });
    const std::uint32_t pixel = sf.info.y;
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t q = ToFixed(color[k] * sf.weight[k]);
      if (q != 0) std::atomic_ref<std::uint64_t>(accum[3 * static_cast<std::size_t>(pixel) + k]).fetch_add(q, std::memory_order_relaxed);
    }
  });
}

}  // namespace rayspace::emu
