// Traversal of one block: the top level tests every (node, triangle) pair, lower levels test the
// children of surviving pairs; CRSH culls top nodes against object spheres first. Mirrors
// gpu/shaders/traverse.comp. The loops are templates in emu/hierarchy.h so `rayspace accuracy` can
// swap the cone-sphere test.
#include <algorithm>

#include <bit>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/hierarchy.h"

namespace rayspace::emu {

float TraversalEpsilon(const SceneBuffers& scene) {
  const glm::vec3 ext = scene.hi - scene.lo;
  return std::max(glm::length(ext), 1e-30f) * 1e-6f;
}

namespace {
// A lambda, not a function pointer, so the test inlines into the traversal loops.
constexpr auto kConeTest = [](const layout::ConeNode& n, glm::vec4 sphere, float eps) { return cone::Test(n, sphere, eps); };
}  // namespace

PairSlots PassTraverseTop(const call::TraverseTop& c) { return TraverseTopWith(kConeTest, c); }

std::vector<std::uint8_t> PassObjectMask(const call::ObjectMask& c) { return ObjectMaskWith(kConeTest, c); }

PairSlots PassTraverseLevel(const call::TraverseLevel& c) { return TraverseLevelWith(kConeTest, c); }

namespace {
bool g_fused_fault = false;
}  // namespace

void SetFusedFaultForTesting(bool on) { g_fused_fault = on; }
bool FusedFaultForTesting() { return g_fused_fault; }

Compacted ConcatenateBlocks(std::vector<std::vector<std::uint32_t>>& parts, const std::vector<std::uint64_t>& tested) {
  Compacted r;
  std::size_t total = 0;
  for (std::size_t b = 0; b < parts.size(); ++b) {
    if (g_fused_fault && !parts[b].empty()) parts[b].pop_back();
    total += parts[b].size();
    r.tested += tested[b];
  }
  r.pairs.reserve(total);
  for (const auto& part : parts) r.pairs.insert(r.pairs.end(), part.begin(), part.end());
  return r;
}

namespace {

// The fused top level with the test on eight triangle spheres at once (cone_simd.h): the slots of a
// block in order, eight of one node at a time, survivors appended in lane order, so the pairs are
// the scalar fused path's.
Compacted TraverseTopCompactedSimd(const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0;
  const std::size_t grid = static_cast<std::size_t>(c.t1 - c.t0) * T;
  return CompactInBlocks(grid, kFusedBlock, [&](std::size_t e0, std::size_t e1, std::vector<std::uint32_t>& out, std::uint64_t& tested) {
    cone::SphereLanes lanes;
    for (std::size_t e = e0; e < e1;) {
      const std::uint32_t node = c.t0 + static_cast<std::uint32_t>(e / T);
      const std::size_t run_end = std::min<std::size_t>(e1, static_cast<std::size_t>(node - c.t0 + 1) * T);
      const std::size_t n = std::min<std::size_t>(8, run_end - e);
      std::uint32_t mask = 0;
      for (std::size_t i = 0; i < 8; ++i) {
        const std::uint32_t tri = c.b0 + static_cast<std::uint32_t>((e + std::min(i, n - 1)) % T);
        const glm::vec4 sp = c.tri_spheres[tri];
        lanes.x[i] = sp.x;
        lanes.y[i] = sp.y;
        lanes.z[i] = sp.z;
        lanes.r[i] = sp.w;
        if (i < n && TopSlotTested(c, node, tri))
          mask |= 1u << i;
      }
      tested += static_cast<std::uint64_t>(std::popcount(mask));
      const std::uint32_t hits = mask ? cone::TestEight(c.top[node], lanes, c.eps) & mask : 0u;
      for (std::size_t i = 0; i < n; ++i)
        if (hits & (1u << i))
          out.push_back(((node - c.t0) << kPairTriangleBits) | static_cast<std::uint32_t>((e + i) % T));
      e += n;
    }
  });
}

bool g_simd = true;

}  // namespace

void SetFusedSimd(bool on) { g_simd = on; }

Compacted PassTraverseTopCompacted(const call::TraverseTop& c) {
  if (g_simd && cone::HaveSimdTest()) return TraverseTopCompactedSimd(c);
  return TraverseTopCompactedWith(kConeTest, c);
}

Compacted PassTraverseLevelCompacted(const call::TraverseLevel& c) { return TraverseLevelCompactedWith(kConeTest, c); }

}  // namespace rayspace::emu
