// The ray-space hierarchy as a tracer: hash, compress, sort, decompress, build, traverse with stream
// reduction, intersect — CRSH (Reis 2015) and RAH (Roger et al. 2007) over the same passes, with the
// thesis's statistics.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/cone.h"
#include "rayspace/object_tree.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/emu/uninit_vector.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

enum class Algorithm { kCrsh, kRah, kRahQuadtree };

// --objects auto: the leaf spread from which a batch takes the object tree, and the object size from
// which every batch does (docs/object-tree.md).
inline constexpr float kAutoTreeSpread = 0.1f;
inline constexpr std::uint32_t kAutoTreeTriangles = 16384;
class HierarchyPasses;

// --levels auto: the fewest levels, at least 2, for which `rays` rays leave at most kAutoTopNodes top
// nodes (rays / subdivision^levels). With a fixed number of levels the top level's nodes, and so its
// tests, grow with the rays; a bounded top keeps the search's growth below linear
// (docs/performance.md, "Levels from the pixels").
inline constexpr std::uint64_t kAutoTopNodes = 512;
// Largest top-level test grid (nodes x triangles) of one traversal call; bigger grids take several
// node groups. The pass-by-pass path holds a call's slots at once, so a frame's memory estimate
// bounds them by it.
inline constexpr std::size_t kMaxTopGrid = std::size_t{1} << 26;
inline int AutoLevels(std::uint64_t rays, int subdivision) {
  int levels = 2;
  std::uint64_t per_top = static_cast<std::uint64_t>(subdivision) * static_cast<std::uint64_t>(subdivision);
  while (levels < 12 && rays > kAutoTopNodes * per_top) {
    per_top *= static_cast<std::uint64_t>(subdivision);
    ++levels;
  }
  return levels;
}

struct HierarchyConfig {
  Algorithm algorithm = Algorithm::kCrsh;
  int subdivision = 8;                    // children per node (4, 8, 16)
  int depth = 2;                          // levels (rah-quadtree: log2 of the image size)
  Reduction reduction = Reduction::kHierarchical;
  int component_size = 64;                // Roger's s for the hierarchical reduction
  std::size_t pair_capacity = 1u << 24;   // pairs a level may hold before the batch is split
  std::uint32_t max_batch_triangles = 1u << layout::kPairTriangleBits;  // triangle ids in a packed pair
  HashConfig hash;
  int image_width = 0, image_height = 0;  // for rah-quadtree
  // The passes to run (nullptr: the emulator's); see emu/backend.h.
  HierarchyPasses* passes = nullptr;
  // Test hook: when set, every final ray-triangle test is logged as (ray index << 32 | primitive).
  std::vector<std::uint64_t>* candidate_log = nullptr;
  // Test hook: when set, every level's compacted pairs are appended, level by level, block by block.
  std::vector<std::vector<std::uint32_t>>* pair_log = nullptr;
  // The fused path (render's default): each level tests and compacts in one pass (traverse.compact)
  // instead of traverse then reduce, with the same pairs in the same order (docs/performance.md).
  // Without `passes` (the emulator's own), the sort and the final tests also take host shortcuts
  // with the same results.
  bool fused = false;
  // --objects tree: the hierarchy descends together with each object's bounding-sphere tree instead
  // of testing every triangle (emu/object_tree_traverse.h); the emulator's passes only.
  bool object_tree = false;
  // --objects auto: each batch takes the tree when its leaves' mean spread (BatchStats::leaf_spread)
  // is at least auto_tree_spread, or when the scene has an object of at least auto_tree_triangles
  // triangles; else flat (docs/object-tree.md, "Which one"). auto_tree_spread 0: off (object_tree
  // decides).
  float auto_tree_spread = 0.0f;
  std::uint32_t auto_tree_triangles = 0;
  ObjectTreeOptions object_tree_options;
  // --cone-test: the traversal's cone-sphere test, conservative (cone::Test) or the thesis's eq. 3.16
  // as printed (cone::PrintedTest, which can lose hits); layout::kConeTest*. The object tree's descent
  // has only the conservative test.
  std::uint32_t cone_test = layout::kConeTestConservative;
  // --leaf-test: kLeafTestNode (every ray of a surviving level-1 pair meets the triangle) or
  // kLeafTestRaySphere (first the triangle's bounding sphere, Roger et al. 2007); the flat descent only
  // (--objects tree already tests every ray against the triangle spheres, as its level 0).
  std::uint32_t leaf_test = layout::kLeafTestNode;
  // --child-merge: kChildMergeSequential (a parent folds its children one after another) or
  // kChildMergePairwise (as a balanced binary tree; cone::ParentNode).
  std::uint32_t child_merge = layout::kChildMergeSequential;
};

// Per ray type and level, as the thesis counts (level `depth` = top).
struct LevelStats {
  std::uint64_t intersections = 0, hits = 0;
};
struct BatchStats {
  std::string batch;
  std::uint32_t kind = 0;
  int bounce = 0;
  std::uint64_t rays = 0, triangles = 0;
  std::vector<LevelStats> levels;  // index L-1 for level L
  std::uint64_t object_sphere_tests = 0, object_sphere_hits = 0;
  // --objects tree: `levels` count every test of a level's cones (against object nodes and triangle
  // spheres); rays (level 0) have their own; the same tests again by the object side: per depth of
  // the tested object node, and against triangle spheres.
  LevelStats ray_level;
  std::vector<LevelStats> object_levels;
  LevelStats object_triangles;
  std::uint64_t tree_rounds = 0;
  // The mean over the level-1 nodes of sin(alpha) + radius / (the scene's bounding radius), a cone
  // wider than a hemisphere counting 1: how far a leaf's rays spread. And whether the batch was
  // traced with the object tree.
  double leaf_spread = 0.0;
  bool object_tree = false;
  std::uint64_t final_tests = 0;
  // --leaf-test ray-sphere: the rays of surviving level-1 pairs tested against the triangle's sphere
  // before the final tests (which then count only the rays that passed); in the total.
  std::uint64_t leaf_sphere_tests = 0;
  std::uint64_t triangle_batches = 0, overflow_splits = 0;
  std::uint64_t Total() const;
  std::uint64_t BruteForce() const { return rays * triangles; }
};

class HierarchyTracer : public Tracer {
 public:
  virtual const std::vector<BatchStats>& Stats() const = 0;
};

// Needs the frame's bounding spheres: the frame hands them over through Tracer::Prepare.
std::unique_ptr<HierarchyTracer> MakeHierarchyTracer(const SceneBuffers& scene, const HierarchyConfig& config);

// ---- the passes (each mirrors its kernel; the calls are documented in emu/calls.h) ---------------
std::vector<std::uint32_t> PassHash(const call::Hash& c);
// Roger et al.'s quadtree key: light index above the Morton code of the pixel (2 * depth bits).
std::vector<std::uint32_t> PassHashQuadtree(In<layout::Ray> rays, std::uint32_t width, int depth);
Chunks PassCompress(const call::Compress& c);
std::vector<std::uint32_t> PassSortChunks(const call::SortChunks& c);
// The fused path's sort: PassSortChunks's permutation (the stable order by key) from a plain host
// radix sort, 11-bit digits, a pass skipped where every key has the same digit.
std::vector<std::uint32_t> SortChunksHost(const call::SortChunks& c);
std::vector<std::uint32_t> PassDecompress(const call::Decompress& c);
std::vector<layout::ConeNode> PassBuildLeaves(const call::BuildLeaves& c);
std::vector<layout::ConeNode> PassBuildParents(const call::BuildParents& c);
std::vector<std::uint8_t> PassObjectMask(const call::ObjectMask& c);
PairSlots PassTraverseTop(const call::TraverseTop& c);
PairSlots PassTraverseLevel(const call::TraverseLevel& c);
std::vector<std::uint32_t> PassReduce(const call::Reduce& c);
std::vector<std::uint32_t> PassIntersect(const call::Intersect& c);

// CSR offsets grouping `count` items `per` at a time (the last group may be smaller).
std::vector<std::uint32_t> FixedGroups(std::size_t count, std::uint32_t per);
using layout::kPairTriangleBits;
using layout::kPairTriangleMask;
// Absolute margin of the cone-sphere test for a scene.
float TraversalEpsilon(const SceneBuffers& scene);

// The traversal passes with the node-sphere test as a parameter (the passes above use cone::Test;
// `rayspace accuracy` swaps in other precisions). test(node, sphere, eps) -> bool.
// Does top-level slot (node, tri) run its test? Not when CRSH's object mask says the node misses the
// sphere of the triangle's object.
inline bool TopSlotTested(const call::TraverseTop& c, std::uint32_t node, std::uint32_t tri) {
  return c.object_mask.empty() ||
         c.object_mask[static_cast<std::size_t>(node) * c.scene->objects.size() + c.scene->info[tri].ids.y];
}

template <typename TestFn>
PairSlots TraverseTopWith(TestFn&& test, const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0;
  const std::size_t grid = static_cast<std::size_t>(c.t1 - c.t0) * T;
  PairSlots s;
  s.flags.resize(grid);
  s.values.resize(grid);
  s.tested.resize(grid);
  // As traverse.comp: one invocation per run of kTraverseTopRun slots of one row, its node read once.
  const std::size_t runs = (T + layout::kTraverseTopRun - 1) / layout::kTraverseTopRun;
  ParallelFor(static_cast<std::size_t>(c.t1 - c.t0) * runs, [&](std::size_t r) {
    const std::uint32_t row = static_cast<std::uint32_t>(r / runs), node = c.t0 + row;
    const std::uint32_t col0 = static_cast<std::uint32_t>(r % runs) * layout::kTraverseTopRun;
    const layout::ConeNode& n = c.top[node];
    for (std::uint32_t col = col0; col < std::min(col0 + layout::kTraverseTopRun, T); ++col) {
      const std::size_t e = static_cast<std::size_t>(row) * T + col;
      const bool tested = TopSlotTested(c, node, c.b0 + col);
      s.tested[e] = tested;
      s.flags[e] = tested && test(n, c.tri_spheres[c.b0 + col], c.eps);
      s.values[e] = (row << kPairTriangleBits) | col;
    }
  });
  return s;
}

// The fused path's levels: what TraverseTopWith / TraverseLevelWith followed by a reduction give
// (Compacted, emu/streams.h), from one pass over blocks of kFusedBlock slots whose survivors are
// concatenated in block order.
inline constexpr std::size_t kFusedBlock = 8192;

// Test hook Settings::fused_fault: drops the last survivor of every block, so the fused-path
// equality test can fail.
//
// The fused path adds the top-level slots it skipped because their group provably misses
// (cone_cull.h) to *Settings::culled_slots when set: a diagnostic, so tests can see that the culling
// ran; the statistics count every slot.

// One block's survivors: sized for the block's slots (plus the lanes' padding), written in place, then
// cut to the survivors.
using BlockSurvivors = UninitVector<std::uint32_t>;

// Concatenates per-block survivors in block order, the blocks copied in parallel.
Compacted ConcatenateBlocks(std::vector<BlockSurvivors>& parts, const std::vector<std::uint64_t>& tested);

// Runs block(i0, i1, survivors, tested) over [0, items) in blocks of `per_block` items, in parallel,
// and concatenates the blocks' survivors in order.
template <typename BlockFn>
Compacted CompactInBlocks(std::size_t items, std::size_t per_block, BlockFn&& block) {
  const std::size_t blocks = (items + per_block - 1) / per_block;
  std::vector<BlockSurvivors> parts(blocks);
  std::vector<std::uint64_t> tested(blocks, 0);
  ParallelForDynamic(blocks, 1, [&](std::size_t b) { block(b * per_block, std::min(items, (b + 1) * per_block), parts[b], tested[b]); });
  return ConcatenateBlocks(parts, tested);
}

template <typename TestFn>
Compacted TraverseTopCompactedWith(TestFn&& test, const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0;
  const std::size_t grid = static_cast<std::size_t>(c.t1 - c.t0) * T;
  return CompactInBlocks(grid, kFusedBlock, [&](std::size_t e0, std::size_t e1, BlockSurvivors& out, std::uint64_t& tested) {
    for (std::size_t e = e0; e < e1; ++e) {
      const std::uint32_t node = c.t0 + static_cast<std::uint32_t>(e / T), tri = c.b0 + static_cast<std::uint32_t>(e % T);
      if (!TopSlotTested(c, node, tri)) continue;
      ++tested;
      if (test(c.top[node], c.tri_spheres[tri], c.eps)) out.push_back(((node - c.t0) << kPairTriangleBits) | (tri - c.b0));
    }
  });
}

template <typename TestFn>
Compacted TraverseLevelCompactedWith(TestFn&& test, const call::TraverseLevel& c) {
  // Blocks of pairs whose children make about kFusedBlock slots.
  const std::size_t per_block = std::max<std::size_t>(1, kFusedBlock / std::max<std::uint32_t>(c.children_max, 1));
  return CompactInBlocks(c.pairs.size(), per_block, [&](std::size_t p0, std::size_t p1, BlockSurvivors& out,
                                                        std::uint64_t& tested) {
    for (std::size_t p = p0; p < p1; ++p) {
      const std::uint32_t parent = c.base_up + (c.pairs[p] >> kPairTriangleBits), tri_local = c.pairs[p] & kPairTriangleMask;
      const glm::vec4 sphere = c.tri_spheres[c.b0 + tri_local];
      const std::uint32_t c0 = c.first[parent], c1 = c.first[parent + 1];
      tested += c1 - c0;
      for (std::uint32_t k = c0; k < c1; ++k)
        if (test(c.nodes[k], sphere, c.eps)) out.push_back(((k - c.base) << kPairTriangleBits) | tri_local);
    }
  });
}

// The fused levels run the cone-sphere test on many lanes where the CPU has AVX2 or AVX-512F
// (cone_simd.h), the same bits as the scalar test; Settings::fused_isa = Isa::kScalar forces the scalar
// loop, and an instruction set the CPU lacks means the best it has.
Compacted PassTraverseTopCompacted(const call::TraverseTop& c);
cone::Isa FusedIsa();  // what the fused levels and the object tree's top level run on
Compacted PassTraverseLevelCompacted(const call::TraverseLevel& c);
// traverse_compact.comp's three dispatches on the workgroup model (emu/src/traverse_compact_wg.cpp):
// the same result as the two above, from the kernel's workgroups, rounds and scans, with its planted
// faults (`--inject traverse.compact:N@emu`).
Compacted TraverseTopCompactedWorkgroups(const call::TraverseTop& c);
// traverse_compact.comp's object-mask binding for `rows` top nodes from the mask's first row
// (`mask`: rows x objects bytes): a word per tile of kCompactRows rows and object, bit r set when row
// r may meet the object (rayspace/contract.h, kTraverseCompactBindMask). The host packs it for the
// kernel and the mirror for itself: one load answers for a tile's rows.
std::vector<std::uint32_t> PackMaskTiles(std::span<const std::uint8_t> mask, std::size_t rows, std::uint32_t objects);
Compacted TraverseLevelCompactedWorkgroups(const call::TraverseLevel& c);
// The traverse.compact calls (emu/calls.h), as the emulator's backend runs them: the workgroup mirror
// when the run asks for the workgroup model or an emulator-side fault is planted in the pass
// (RunsWorkgroupMirror, emu/workgroup_ops.h), the lanes above otherwise.
Compacted PassTraverseTopCompacted(const call::TraverseTopCompacted& c);
Compacted PassTraverseLevelCompacted(const call::TraverseLevelCompacted& c);

template <typename TestFn>
std::vector<std::uint8_t> ObjectMaskWith(TestFn&& test, const call::ObjectMask& c) {
  const std::size_t objects = c.object_spheres.size();
  std::vector<std::uint8_t> mask(c.top.size() * objects, 0);
  ParallelFor(mask.size(), [&](std::size_t e) { mask[e] = test(c.top[e / objects], c.object_spheres[e % objects], c.eps); });
  return mask;
}

template <typename TestFn>
PairSlots TraverseLevelWith(TestFn&& test, const call::TraverseLevel& c) {
  PairSlots s;
  s.flags.assign(c.pairs.size() * c.children_max, 0);
  s.values.assign(c.pairs.size() * c.children_max, 0);
  s.tested.assign(c.pairs.size(), 0);
  ParallelFor(c.pairs.size(), [&](std::size_t p) {
    const std::uint32_t parent = c.base_up + (c.pairs[p] >> kPairTriangleBits), tri_local = c.pairs[p] & kPairTriangleMask;
    const glm::vec4 sphere = c.tri_spheres[c.b0 + tri_local];
    const std::uint32_t c0 = c.first[parent], c1 = c.first[parent + 1];
    s.tested[p] = static_cast<std::uint8_t>(c1 - c0);
    for (std::uint32_t k = c0; k < c1; ++k) {
      const std::size_t slot = p * c.children_max + (k - c0);
      s.flags[slot] = test(c.nodes[k], sphere, c.eps);
      s.values[slot] = ((k - c.base) << kPairTriangleBits) | tri_local;
    }
  });
  return s;
}

// Atomic minimum of the packed (distance, primitive) hit of `ray`: the closest hit whatever the order.
inline void RecordClosestHit(std::vector<std::uint64_t>& hits, std::uint32_t ray, std::uint64_t packed) {
  std::atomic_ref<std::uint64_t> a(hits[ray]);
  std::uint64_t cur = a.load(std::memory_order_relaxed);
  while (packed < cur && !a.compare_exchange_weak(cur, packed, std::memory_order_relaxed)) {
  }
}

// The final tests with the ray-triangle test and the closest-hit record as parameters (PassIntersect
// uses the watertight test and RecordClosestHit; `rayspace accuracy` swaps in other tests):
// hit(ray, triangle, t&) -> bool; closest(ray index, ray, t, primitive). Shadow rays store 1. With
// kLeafTestRaySphere a ray that misses the triangle's sphere is neither tested nor counted; a ray
// leaving the triangle's own surface is counted as today's tests count it, then skipped.
template <typename HitFn, typename ClosestFn>
std::vector<std::uint32_t> IntersectWith(HitFn&& hit, ClosestFn&& closest, const call::Intersect& c) {
  std::vector<std::uint32_t> tests(c.pairs.size());
  ParallelFor(c.pairs.size(), [&](std::size_t p) {
    const std::uint32_t node = c.base1 + (c.pairs[p] >> kPairTriangleBits), prim = c.b0 + (c.pairs[p] & kPairTriangleMask);
    const layout::Triangle& tri = c.scene->triangles[prim];
    const bool sphere_first = c.leaf_test == layout::kLeafTestRaySphere;
    std::uint32_t performed = 0;
    for (std::uint32_t j = c.first1[node]; j < c.first1[node + 1]; ++j) {
      const std::uint32_t ray = c.order[j];
      const layout::Ray& r = c.rays[ray];
      if (sphere_first && !cone::RayMayMeetSphere(r, c.tri_spheres[prim], c.eps)) continue;
      ++performed;
      if (prim == r.info.y) continue;  // the surface the ray leaves
      float t = 0.0f;
      if (!hit(r, tri, t)) continue;
      if (c.occluded)
        std::atomic_ref<std::uint32_t>((*c.occluded)[ray]).store(1u, std::memory_order_relaxed);
      else
        closest(ray, r, t, prim);
    }
    tests[p] = performed;
  });
  return tests;
}

// Stream reduction of (flag, value) slots to the flagged values in slot order.
std::vector<std::uint32_t> ReduceScan(In<std::uint8_t> flags, In<std::uint32_t> values);
std::vector<std::uint32_t> ReduceHierarchical(In<std::uint8_t> flags, In<std::uint32_t> values, int component);

}  // namespace rayspace::emu
