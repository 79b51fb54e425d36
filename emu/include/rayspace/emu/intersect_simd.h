// The fused path's final ray-triangle tests: the rays below a level-1 node tested against the pair's
// triangle eight at a time (AVX2, emu/src/simd/intersect_lanes_avx2.cpp), each lane the scalar
// watertight test bit for bit; the same tests, hits and counts as PassIntersect.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/emu/calls.h"

namespace rayspace::emu {

// A batch's rays in the hierarchy's order (position j holds ray order[j]), set up once for the
// watertight test (SetupWatertight), one array per field, each padded by eight entries.
struct WatertightArrays {
  std::vector<float> ox, oy, oz, dx, dy, dz, sx, sy, tmin, tmax;
  std::vector<std::int32_t> kx, ky, kz;
  std::size_t size() const { return ox.size() - kPad; }
  static constexpr std::size_t kPad = 8;
};
WatertightArrays ToWatertightArrays(std::span<const layout::Ray> rays, std::span<const std::uint32_t> order);

// What PassIntersect returns and writes, given the arrays of c.rays in c.order.
std::vector<std::uint32_t> PassIntersectLanes(const call::Intersect& c, const WatertightArrays& w);
// Whether PassIntersectLanes uses the lanes (where the CPU has AVX2) or the scalar test (for tests).
void SetIntersectLanes(bool on);

}  // namespace rayspace::emu
