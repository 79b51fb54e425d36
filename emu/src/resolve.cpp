// The final resolve: fixed-point accumulator to 8-bit RGB with display gamma 2. Mirrors
// gpu/shaders/resolve.comp.
#include <cmath>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<std::uint8_t> PassResolve(const call::Resolve& c) {
  const In<std::uint64_t> accum = c.accum;
  std::vector<std::uint8_t> rgb(accum.size());
  ParallelFor(accum.size(), [&](std::size_t i) {
    const float v = static_cast<float>(accum[i]) / layout::kAccumScale;
    const float g = std::sqrt(Clamp(v, 0.0f, 1.0f));  // display gamma 2: sqrt is exact on both sides
    rgb[i] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(g * 255.0f + 0.5f));
  });
  return rgb;
}

}  // namespace rayspace::emu
