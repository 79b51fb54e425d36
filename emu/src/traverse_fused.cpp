// The fused traversal's levels with the multi-lane cone-sphere test (cone_simd.h): each block tests
// its slots in slot order, a top node against runs of its batch's triangle spheres, a pair's parent
// against its children; survivors are written in lane order, so the pairs are the scalar fused
// loops' (TraverseTopCompactedWith, TraverseLevelCompactedWith), and those are the passes'. The top
// level skips the groups of spheres a node provably misses (cone_cull.h): no test would pass there.
#include <algorithm>
#include <atomic>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/cone_cull.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {


// Triangles [t0, t1) of a batch (batch-local) that share an object. A scene's objects own contiguous
// triangles, so a batch has few runs; without an object mask the batch is one run, always tested.
struct ObjectRun {
  std::uint32_t t0, t1, object;
};

std::vector<ObjectRun> ObjectRuns(const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0;
  if (c.object_mask.empty()) return {{0, T, 0}};
  std::vector<ObjectRun> runs;
  for (std::uint32_t t = 0; t < T; ++t) {
    const std::uint32_t object = c.scene->info[c.b0 + t].ids.y;
    if (runs.empty() || runs.back().object != object)
      runs.push_back({t, t + 1, object});
    else
      runs.back().t1 = t + 1;
  }
  return runs;
}

bool RunTested(const call::TraverseTop& c, std::uint32_t node, const ObjectRun& run) {
  return c.object_mask.empty() || c.object_mask[static_cast<std::size_t>(node) * c.scene->objects.size() + run.object];
}

// The top level's spheres of one batch: their lanes and their groups.
struct TopSpheres {
  cone::SphereArrays lanes;
  cone::SphereGroups coarse, fine;
};

// Spheres [lo, hi) of one node, less the groups the node provably misses (cone_cull.h); what is
// left is tested in runs as long as possible, in order.
std::size_t TestCulled(const call::TraverseTop& c, const TopSpheres& s, const cone::CullNode& cull, std::uint32_t node,
                       std::uint32_t lo, std::uint32_t hi, std::uint32_t* out) {
  const layout::ConeNode& n = c.top[node];
  const std::uint32_t first = (node - c.t0) << kPairTriangleBits;
  std::size_t count = 0;
  std::uint32_t from = lo;
  std::uint64_t culled = 0;
  const cone::Isa isa = FusedIsa();
  auto skip = [&](std::uint32_t gl, std::uint32_t gh) {
    if (from < gl) count += cone::TestSpheres(isa, n, s.lanes, from, gl, c.eps, first, 0, out + count);
    culled += gh - gl;
    from = gh;
  };
  constexpr std::uint32_t F = cone::kCullGroup, C = cone::kCullCoarse;
  for (std::uint32_t g = lo / F; g * F < hi;) {
    if (g % (C / F) == 0 || g == lo / F) {
      const std::uint32_t cg = g / (C / F);
      if (cone::GroupMisses(cull, s.coarse, cg)) {
        skip(std::max(lo, cg * C), std::min(hi, (cg + 1) * C));
        g = (cg + 1) * (C / F);
        continue;
      }
    }
    if (cone::GroupMisses(cull, s.fine, g)) skip(std::max(lo, g * F), std::min(hi, (g + 1) * F));
    ++g;
  }
  if (from < hi) count += cone::TestSpheres(isa, n, s.lanes, from, hi, c.eps, first, 0, out + count);
  if (std::uint64_t* sink = CurrentSettings().culled_slots; culled && sink)
    std::atomic_ref<std::uint64_t>(*sink).fetch_add(culled, std::memory_order_relaxed);
  return count;
}

// The batch-local triangles [ta, tb) of one top node: the object runs the node's mask keeps.
void TestNodeRow(const call::TraverseTop& c, const TopSpheres& spheres, const std::vector<ObjectRun>& runs,
                 std::uint32_t node, std::uint32_t ta, std::uint32_t tb, BlockSurvivors& buf, std::size_t& n,
                 std::uint64_t& tested) {
  const cone::CullNode cull = cone::CullNodeOf(c.top[node], c.eps);
  auto run = std::upper_bound(runs.begin(), runs.end(), ta, [](std::uint32_t t, const ObjectRun& r) { return t < r.t1; });
  for (; run != runs.end() && run->t0 < tb; ++run) {
    if (!RunTested(c, node, *run)) continue;
    const std::uint32_t lo = std::max(ta, run->t0), hi = std::min(tb, run->t1);
    tested += hi - lo;
    n += TestCulled(c, spheres, cull, node, lo, hi, buf.data() + n);
  }
}

}  // namespace


cone::Isa FusedIsa() {
  const std::optional<cone::Isa> isa = CurrentSettings().fused_isa;
  return isa && cone::Runs(*isa) ? *isa : cone::BestIsa();
}

// --cone-test printed has no lanes: the scalar fused loops give the same slot order and test counts.
Compacted PassTraverseTopCompacted(const call::TraverseTop& c) {
  if (c.cone_test == layout::kConeTestPrinted) return TraverseTopCompactedWith(cone::kPrintedTestFn, c);
  if (c.cone_test == layout::kConeTestPrintedSigned) return TraverseTopCompactedWith(cone::kPrintedSignedTestFn, c);
  const std::uint32_t T = c.b1 - c.b0;
  const std::size_t grid = static_cast<std::size_t>(c.t1 - c.t0) * T;
  const std::span<const glm::vec4> batch = c.tri_spheres.subspan(c.b0, T);
  const TopSpheres spheres{cone::ToArrays(batch), cone::GroupsOf(batch, cone::kCullCoarse), cone::GroupsOf(batch, cone::kCullGroup)};
  const std::vector<ObjectRun> runs = ObjectRuns(c);
  return CompactInBlocks(grid, kFusedBlock, [&](std::size_t e0, std::size_t e1, BlockSurvivors& out, std::uint64_t& tested) {
    BlockSurvivors buf(e1 - e0 + cone::kLanePad);  // freed with the block: the heap reuses it for the next
    std::size_t n = 0;
    for (std::size_t e = e0; e < e1;) {
      const std::uint32_t node = c.t0 + static_cast<std::uint32_t>(e / T), ta = static_cast<std::uint32_t>(e % T);
      const std::uint32_t tb = static_cast<std::uint32_t>(std::min<std::size_t>(T, ta + (e1 - e)));
      TestNodeRow(c, spheres, runs, node, ta, tb, buf, n, tested);
      e += tb - ta;
    }
    out.assign(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  });
}

Compacted PassTraverseLevelCompacted(const call::TraverseLevel& c) {
  if (c.cone_test == layout::kConeTestPrinted) return TraverseLevelCompactedWith(cone::kPrintedTestFn, c);
  if (c.cone_test == layout::kConeTestPrintedSigned) return TraverseLevelCompactedWith(cone::kPrintedSignedTestFn, c);
  const cone::NodeArrays nodes = cone::ToArrays(c.nodes);
  const cone::PairLevel lv{c.pairs, c.first, c.base_up, c.base, c.tri_spheres.data() + c.b0};
  const std::size_t per_block = std::max<std::size_t>(1, kFusedBlock / std::max<std::uint32_t>(c.children_max, 1));
  return CompactInBlocks(c.pairs.size(), per_block, [&](std::size_t p0, std::size_t p1, BlockSurvivors& out,
                                                        std::uint64_t& tested) {
    std::size_t children = 0;
    for (std::size_t p = p0; p < p1; ++p) {
      const std::uint32_t parent = c.base_up + (c.pairs[p] >> kPairTriangleBits);
      children += c.first[parent + 1] - c.first[parent];
    }
    BlockSurvivors buf(children + cone::kLanePad);
    const std::size_t n = cone::TestPairs(FusedIsa(), nodes, lv, p0, p1, c.eps, buf.data(), tested);
    out.assign(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  });
}

}  // namespace rayspace::emu
