// The final resolve: fixed-point accumulator to 8-bit RGB with display gamma 2. Mirrors
// gpu/shaders/resolve.comp.
#include <cmath>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<std::uint8_t> PassResolve(const call::Resolve& c) {
  const gpu::FrameConstants& fc = c.frame;
  const In<std::uint64_t> accum = c.accum;
  const std::size_t npix = static_cast<std::size_t>(fc.dims.x) * fc.dims.y;
  std::vector<std::uint8_t> rgb(npix * 3);
  ParallelFor(npix * 3, [&](std::size_t i) {
    const float c = static_cast<float>(accum[i]) / gpu::kAccumScale;
    const float g = std::sqrt(Clamp(c, 0.0f, 1.0f));  // display gamma 2: sqrt is exact on both sides
    rgb[i] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(g * 255.0f + 0.5f));
  });
  return rgb;
}

}  // namespace rayspace::emu
