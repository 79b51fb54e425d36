// The fused path's final ray-triangle tests: the rays below a level-1 node tested against the pair's
// triangle sixteen (AVX-512F) or eight (AVX2) at a time (emu/src/simd/intersect_lanes.inl), each
// lane the scalar watertight test bit for bit; the same hits and tests as PassIntersect.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/uninit_vector.h"

namespace rayspace::emu {

// A batch's rays in the hierarchy's order (position j holds ray order[j]), set up once for the
// watertight test (SetupWatertight), one array per field, each padded by sixteen zeros. Every entry
// is written once (no zero-fill first: the rays' own writes fault the pages in, in parallel).
struct WatertightArrays {
  UninitVector<float> ox, oy, oz, dx, dy, dz, sx, sy, tmin, tmax;
  UninitVector<std::int32_t> kx, ky, kz;
  std::size_t size() const { return ox.size() - kPad; }
  static constexpr std::size_t kPad = 16;
};
WatertightArrays ToWatertightArrays(std::span<const layout::Ray> rays, std::span<const std::uint32_t> order);

// What PassIntersect writes, given the arrays of c.rays in c.order, and the sum of the per-pair tests
// it returns: the host path needs only the total, not a count for every pair.
std::uint64_t IntersectLanes(const call::Intersect& c, const WatertightArrays& w);
// A triangle as the lanes read it: vertices and plane normal (PlaneNormalOf), set up once.
struct LanesTriangle {
  float v[12];
};
LanesTriangle PrepareLanesTriangle(const layout::Triangle& t);
// Rays [j0, j1) of c.order against scene triangle `prim`, one by one with the scalar watertight test,
// recorded into c.hits or c.occluded as PassIntersect records them (c.pairs is not read).
void IntersectRaysScalar(const call::Intersect& c, std::uint32_t prim, std::uint32_t j0, std::uint32_t j1);
// Rays [j0, j1) of c.order (set up in w) against scene triangle `prim` (set up in tri), recorded
// into c.hits or c.occluded as PassIntersect records them (c.pairs is not read): the joint
// descent's final tests. Scalar when the lanes are.
void IntersectRaysLanes(const call::Intersect& c, const WatertightArrays& w, const LanesTriangle& tri, std::uint32_t prim,
                        std::uint32_t j0, std::uint32_t j1);
// The lanes IntersectLanes uses are Settings::intersect_isa (scalar, AVX2 or AVX-512F); one the
// CPU lacks means the best it has.

}  // namespace rayspace::emu
