// The final tests eight rays at a time (intersect_simd.h). The per-ray setup is computed once per
// batch instead of once per test, the triangle's plane normal once per pair; both by the scalar
// test's own functions, so only the per-lane part lives in the AVX2 unit.
#include "rayspace/emu/intersect_simd.h"

#include <algorithm>
#include <atomic>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/parallel.h"
#include "simd/intersect_lanes.h"

namespace rayspace::emu {
namespace {

bool g_lanes = true;

bool HaveLanes() { return g_lanes && __builtin_cpu_supports("avx2"); }

intersect_lanes::RayArrays View(const WatertightArrays& w) {
  return {w.ox.data(), w.oy.data(), w.oz.data(), w.dx.data(),   w.dy.data(),   w.dz.data(),   w.sx.data(),
          w.sy.data(), w.tmin.data(), w.tmax.data(), w.kx.data(), w.ky.data(), w.kz.data()};
}

intersect_lanes::Triangle LanesTriangle(const layout::Triangle& t) {
  const glm::vec3 v0 = Xyz(t.v0), v1 = Xyz(t.v1), v2 = Xyz(t.v2);
  const glm::vec3 n = PlaneNormalOf(v0, v1, v2);
  return {{v0.x, v0.y, v0.z}, {v1.x, v1.y, v1.z}, {v2.x, v2.y, v2.z}, {n.x, n.y, n.z}};
}

// The call's triangles (batch-local, up to the highest its pairs name) with their plane normals,
// computed once rather than once per pair.
std::vector<intersect_lanes::Triangle> BatchTriangles(const call::Intersect& c) {
  std::uint32_t count = 0;
  for (std::uint32_t pair : c.pairs) count = std::max(count, (pair & kPairTriangleMask) + 1);
  std::vector<intersect_lanes::Triangle> tris(count);
  ParallelFor(count, [&](std::size_t t) { tris[t] = LanesTriangle(c.scene->triangles[c.b0 + t]); });
  return tris;
}

// The rays [j0, j1) of one pair against its triangle, recorded as IntersectWith records them.
void TestPair(const call::Intersect& c, const intersect_lanes::RayArrays& r, const intersect_lanes::Triangle& tri, std::uint32_t prim,
              std::uint32_t j0, std::uint32_t j1) {
  float t[8];
  for (std::uint32_t j = j0; j < j1; j += 8) {
    std::uint32_t bits = intersect_lanes::EightAvx2(r, tri, j, t);
    if (j1 - j < 8) bits &= (1u << (j1 - j)) - 1u;
    for (; bits; bits &= bits - 1) {
      const std::uint32_t i = static_cast<std::uint32_t>(__builtin_ctz(bits)), ray = c.order[j + i];
      if (prim == c.rays[ray].info.y) continue;  // the surface the ray leaves
      if (c.occluded)
        std::atomic_ref<std::uint32_t>((*c.occluded)[ray]).store(1u, std::memory_order_relaxed);
      else
        RecordClosestHit(*c.hits, ray, PackHit(t[i], prim));
    }
  }
}

}  // namespace

void SetIntersectLanes(bool on) { g_lanes = on; }

WatertightArrays ToWatertightArrays(std::span<const layout::Ray> rays, std::span<const std::uint32_t> order) {
  const std::size_t n = order.size(), padded = n + WatertightArrays::kPad;
  WatertightArrays w;
  for (auto* v : {&w.ox, &w.oy, &w.oz, &w.dx, &w.dy, &w.dz, &w.sx, &w.sy, &w.tmin, &w.tmax}) v->assign(padded, 0.0f);
  for (auto* v : {&w.kx, &w.ky, &w.kz}) v->assign(padded, 0);
  ParallelFor(n, [&](std::size_t j) {
    const layout::Ray& r = rays[order[j]];
    const WatertightRay s = SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax));
    w.ox[j] = s.org.x, w.oy[j] = s.org.y, w.oz[j] = s.org.z;
    w.dx[j] = s.dir.x, w.dy[j] = s.dir.y, w.dz[j] = s.dir.z;
    w.sx[j] = s.sx, w.sy[j] = s.sy, w.kx[j] = s.kx, w.ky[j] = s.ky, w.kz[j] = s.kz;
    w.tmin[j] = r.origin_tmin.w, w.tmax[j] = r.direction_tmax.w;
  });
  return w;
}

std::vector<std::uint32_t> PassIntersectLanes(const call::Intersect& c, const WatertightArrays& w) {
  if (!HaveLanes()) return PassIntersect(c);
  const intersect_lanes::RayArrays r = View(w);
  const std::vector<intersect_lanes::Triangle> tris = BatchTriangles(c);
  std::vector<std::uint32_t> tests(c.pairs.size());
  ParallelForDynamic(c.pairs.size(), 256, [&](std::size_t p) {
    const std::uint32_t node = c.base1 + (c.pairs[p] >> kPairTriangleBits), local = c.pairs[p] & kPairTriangleMask;
    const std::uint32_t j0 = c.first1[node], j1 = c.first1[node + 1];
    tests[p] = j1 - j0;
    TestPair(c, r, tris[local], c.b0 + local, j0, j1);
  });
  return tests;
}

}  // namespace rayspace::emu
