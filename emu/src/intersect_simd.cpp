// The final tests many rays at a time (intersect_simd.h). The per-ray setup is computed once per
// batch instead of once per test, the triangle's plane normal once per call; both by the scalar
// test's own functions, so only the per-lane part lives in the instruction-set units.
#include "rayspace/emu/intersect_simd.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <numeric>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/parallel.h"
#include "simd/intersect_lanes.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {

cone::Isa IntersectIsa() {
  const std::optional<cone::Isa> isa = CurrentSettings().intersect_isa;
  return isa && cone::Runs(*isa) ? *isa : cone::BestIsa();
}

intersect_lanes::RayArrays View(const WatertightArrays& w) {
  return {w.ox.data(), w.oy.data(), w.oz.data(), w.dx.data(),   w.dy.data(),   w.dz.data(),   w.sx.data(),
          w.sy.data(), w.tmin.data(), w.tmax.data(), w.kx.data(), w.ky.data(), w.kz.data()};
}

intersect_lanes::Triangle ToLanes(const layout::Triangle& t) {
  const glm::vec3 v0 = Xyz(t.v0), v1 = Xyz(t.v1), v2 = Xyz(t.v2);
  const glm::vec3 n = PlaneNormalOf(v0, v1, v2);
  return {{v0.x, v0.y, v0.z}, {v1.x, v1.y, v1.z}, {v2.x, v2.y, v2.z}, {n.x, n.y, n.z}};
}

// The triangles a pair can name (batch-local: b0 and the next 2^kPairTriangleBits) with their
// plane normals, computed once per call rather than once per pair.
std::vector<intersect_lanes::Triangle> BatchTriangles(const call::Intersect& c) {
  const std::size_t count = std::min<std::size_t>(c.scene->triangles.size() - c.b0, std::size_t{kPairTriangleMask} + 1);
  std::vector<intersect_lanes::Triangle> tris(count);
  ParallelFor(count, [&](std::size_t t) { tris[t] = ToLanes(c.scene->triangles[c.b0 + t]); });
  return tris;
}

// The rays [j0, j1) against one triangle, W at a time, recorded as IntersectWith records them.
template <int W>
void TestRays(const call::Intersect& c, const intersect_lanes::RayArrays& r, const intersect_lanes::Triangle& tri, std::uint32_t prim,
              std::uint32_t j0, std::uint32_t j1) {
  float t[W];
  for (std::uint32_t j = j0; j < j1; j += W) {
    std::uint32_t bits = W == 16 ? intersect_lanes::RaysAvx512(r, tri, j, t) : intersect_lanes::RaysAvx2(r, tri, j, t);
    if (j1 - j < W) bits &= (1u << (j1 - j)) - 1u;
    for (; bits; bits &= bits - 1) {
      const std::uint32_t i = static_cast<std::uint32_t>(__builtin_ctz(bits)), ray = c.order[j + i];
      if (prim == c.rays[ray].info.y) continue;  // the surface the ray leaves
      // A hit the sphere test would have kept from its test (none, the test being conservative,
      // but the emulator states what the kernel does).
      if (c.leaf_test == layout::kLeafTestRaySphere && !cone::RayMayMeetSphere(c.rays[ray], c.tri_spheres[prim], c.eps)) continue;
      if (c.occluded)
        std::atomic_ref<std::uint32_t>((*c.occluded)[ray]).store(1u, std::memory_order_relaxed);
      else
        RecordClosestHit(*c.hits, ray, PackHit(t[i], prim));
    }
  }
}

std::uint32_t FirstRay(const call::Intersect& c, std::size_t p) { return c.first1[c.base1 + (c.pairs[p] >> kPairTriangleBits)]; }
std::uint32_t EndRay(const call::Intersect& c, std::size_t p) { return c.first1[c.base1 + (c.pairs[p] >> kPairTriangleBits) + 1]; }

// Where runs start: consecutive pairs of one triangle whose nodes' rays are adjacent (a level-1
// parent's children that all passed) are one run of rays, the same tests in fuller lane groups.
bool RunStartsAt(const call::Intersect& c, std::size_t p) {
  return p == 0 || (c.pairs[p] & kPairTriangleMask) != (c.pairs[p - 1] & kPairTriangleMask) || EndRay(c, p - 1) != FirstRay(c, p);
}

// The runs found and tested chunk by chunk: a chunk owns the runs that start in it (one may reach
// past its end) and counts their tests, so no array of run starts is built. Every record is an
// atomic minimum or a store of 1, so the chunks' order changes no bit.
constexpr std::size_t kRunChunk = 4096;

// The tests a run of rays [j0, j1) counts against `prim`: every ray, or with the leaf sphere test
// the rays whose sphere test passes (the lanes test every ray; only the count and the hits see it).
std::uint64_t RunTests(const call::Intersect& c, std::uint32_t prim, std::uint32_t j0, std::uint32_t j1) {
  if (c.leaf_test != layout::kLeafTestRaySphere) return j1 - j0;
  std::uint64_t n = 0;
  for (std::uint32_t j = j0; j < j1; ++j) n += cone::RayMayMeetSphere(c.rays[c.order[j]], c.tri_spheres[prim], c.eps);
  return n;
}

template <int W>
std::uint64_t TestRuns(const call::Intersect& c, const WatertightArrays& w) {
  const intersect_lanes::RayArrays r = View(w);
  const std::vector<intersect_lanes::Triangle> tris = BatchTriangles(c);
  const std::size_t n = c.pairs.size(), chunks = (n + kRunChunk - 1) / kRunChunk;
  std::vector<std::uint64_t> tests(chunks, 0);
  ParallelForDynamic(chunks, 1, [&](std::size_t k) {
    const std::size_t end = std::min(n, (k + 1) * kRunChunk);
    std::size_t p = k * kRunChunk;
    while (p < end && !RunStartsAt(c, p)) ++p;
    while (p < end) {
      std::size_t q = p + 1;
      while (q < n && !RunStartsAt(c, q)) ++q;
      const std::uint32_t local = c.pairs[p] & kPairTriangleMask, j0 = FirstRay(c, p), j1 = EndRay(c, q - 1);
      TestRays<W>(c, r, tris[local], c.b0 + local, j0, j1);
      tests[k] += RunTests(c, c.b0 + local, j0, j1);
      p = q;
    }
  });
  return std::accumulate(tests.begin(), tests.end(), std::uint64_t{0});
}

}  // namespace

static_assert(sizeof(emu::LanesTriangle) == sizeof(intersect_lanes::Triangle));

emu::LanesTriangle PrepareLanesTriangle(const layout::Triangle& t) { return std::bit_cast<emu::LanesTriangle>(ToLanes(t)); }

void IntersectRaysLanes(const call::Intersect& c, const WatertightArrays& w, const emu::LanesTriangle& prepared, std::uint32_t prim,
                        std::uint32_t j0, std::uint32_t j1) {
  const intersect_lanes::Triangle tri = std::bit_cast<intersect_lanes::Triangle>(prepared);
  const cone::Isa isa = IntersectIsa();
  if (isa == cone::Isa::kAvx512) return TestRays<16>(c, View(w), tri, prim, j0, j1);
  if (isa == cone::Isa::kAvx2) return TestRays<8>(c, View(w), tri, prim, j0, j1);
  IntersectRaysScalar(c, prim, j0, j1);
}

void IntersectRaysScalar(const call::Intersect& c, std::uint32_t prim, std::uint32_t j0, std::uint32_t j1) {
  const layout::Triangle& t = c.scene->triangles[prim];
  for (std::uint32_t j = j0; j < j1; ++j) {
    const std::uint32_t ray = c.order[j];
    const layout::Ray& r = c.rays[ray];
    float th = 0.0f;
    if (c.leaf_test == layout::kLeafTestRaySphere && !cone::RayMayMeetSphere(r, c.tri_spheres[prim], c.eps)) continue;
    if (prim == r.info.y || !IntersectWatertight(SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax)), Xyz(t.v0), Xyz(t.v1),
                                                 Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th))
      continue;
    if (c.occluded)
      std::atomic_ref<std::uint32_t>((*c.occluded)[ray]).store(1u, std::memory_order_relaxed);
    else
      RecordClosestHit(*c.hits, ray, PackHit(th, prim));
  }
}


WatertightArrays ToWatertightArrays(std::span<const layout::Ray> rays, std::span<const std::uint32_t> order) {
  const std::size_t n = order.size(), padded = n + WatertightArrays::kPad;
  WatertightArrays w;
  auto padded_array = [&](auto& v) {  // the rays' entries are written below; only the pad is zeroed
    v.resize(padded);
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(n), v.end(), 0);
  };
  for (auto* v : {&w.ox, &w.oy, &w.oz, &w.dx, &w.dy, &w.dz, &w.sx, &w.sy, &w.tmin, &w.tmax}) padded_array(*v);
  for (auto* v : {&w.kx, &w.ky, &w.kz}) padded_array(*v);
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

std::uint64_t IntersectLanes(const call::Intersect& c, const WatertightArrays& w) {
  const cone::Isa isa = IntersectIsa();
  if (isa == cone::Isa::kScalar) {
    const std::vector<std::uint32_t> tests = PassIntersect(c);
    return std::accumulate(tests.begin(), tests.end(), std::uint64_t{0});
  }
  return c.pairs.empty() ? 0 : (isa == cone::Isa::kAvx512 ? TestRuns<16> : TestRuns<8>)(c, w);
}

}  // namespace rayspace::emu
