// The ray-space hierarchy as a tracer: hash, compress, sort, decompress, build, traverse with stream
// reduction, intersect — CRSH (Reis 2015) and RAH (Roger et al. 2007) over the same passes, with the
// thesis's statistics.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

enum class Algorithm { kCrsh, kRah, kRahQuadtree };
enum class Reduction { kHierarchical, kScan };

struct HashConfig {
  int light_bits = 4;      // shadow keys: light index in the high bits
  int polar_bits = 14;     // shadow keys: cos(theta) cells
  int azimuth_bits = 14;   // shadow keys: azimuth cells (pseudo-angle, no trigonometry)
  int origin_bits = 6;     // reflection/refraction: cells per axis of the scene box (x3, interleaved)
  int direction_bits = 7;  // reflection/refraction: cells per direction coordinate (x2)
};

class HierarchyPasses;

struct HierarchyConfig {
  Algorithm algorithm = Algorithm::kCrsh;
  int subdivision = 8;                    // children per node (4, 8, 16)
  int depth = 2;                          // levels (rah-quadtree: log2 of the image size)
  Reduction reduction = Reduction::kHierarchical;
  int component_size = 64;                // Roger's s for the hierarchical reduction
  std::size_t pair_capacity = 1u << 24;   // pairs a level may hold before the batch is split
  std::uint32_t max_batch_triangles = 1u << gpu::kPairTriangleBits;  // triangle ids in a packed pair
  HashConfig hash;
  int image_width = 0, image_height = 0;  // for rah-quadtree
  // The passes to run (nullptr: the emulator's); see emu/backend.h.
  HierarchyPasses* passes = nullptr;
  // Test hook: when set, every final ray-triangle test is logged as (ray index << 32 | primitive).
  std::vector<std::uint64_t>* candidate_log = nullptr;
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
  std::uint64_t final_tests = 0;
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

// ---- the passes, exposed for tests ----------------------------------------------------------------
// 32-bit sort key per ray (docs/hierarchy.md, "Hash keys": shadow = light | direction; others = origin | direction).
// The scene's bounding box bounds the origin cells.
std::vector<std::uint32_t> PassHash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const HashConfig& h);
struct Chunks {
  std::vector<std::uint32_t> key, base, size;
};
Chunks PassCompress(const std::vector<std::uint32_t>& keys);
// Stable LSD radix sort of chunk keys (8 bits per pass); returns the chunk indices in sorted order.
std::vector<std::uint32_t> PassSortChunks(const std::vector<std::uint32_t>& chunk_keys);
// Sorted ray order: the rays of each chunk, chunks in sorted order.
std::vector<std::uint32_t> PassDecompress(const Chunks& chunks, const std::vector<std::uint32_t>& sorted_chunks);

// Hierarchy build (docs/hierarchy.md). first is a CSR offset array: node i covers items
// [first[i], first[i+1]) (sorted rays through `order` for level 1, nodes of the level below above).
std::vector<gpu::ConeNode> PassBuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                           const std::vector<std::uint32_t>& first);
std::vector<gpu::ConeNode> PassBuildParents(const std::vector<gpu::ConeNode>& below, const std::vector<std::uint32_t>& first);
// CSR offsets grouping `count` items `per` at a time (the last group may be smaller).
std::vector<std::uint32_t> FixedGroups(std::size_t count, std::uint32_t per);

// ---- traversal of one block: top nodes [t0, t1) x triangles [b0, b1) -------------------------------
// Pairs are packed (node id - level base) << gpu::kPairTriangleBits | (triangle - b0) (rayspace/contract.h).
struct PairSlots {
  std::vector<std::uint8_t> flags;    // 1 where the slot's pair survives the cone-sphere test
  std::vector<std::uint32_t> values;  // the packed pair of each slot
  std::vector<std::uint8_t> tested;   // top level: 1 where a test ran; lower levels: children per pair
};
using gpu::kPairTriangleBits;
using gpu::kPairTriangleMask;
// Absolute margin of the cone-sphere test for a scene.
float TraversalEpsilon(const SceneBuffers& scene);
// CRSH's object culling: 1 where top node e / objects may meet object sphere e % objects.
std::vector<std::uint8_t> PassObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                         float eps);
// Top level; `object_mask` (top nodes x objects, CRSH) empty = no object culling.
PairSlots PassTraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                          std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                          const std::vector<std::uint8_t>& object_mask, float eps);
// One level down: the node of each pair (base_up + id) tests its children [first[.], first[. + 1]) among
// `nodes`; slots are pairs x children_max; new ids are relative to `base`.
PairSlots PassTraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                            const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                            std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                            float eps);
// Final tests of surviving level-1 pairs: every ray of the node (first1 over `order`) against the
// triangle; closest hits by atomic minimum, shadow rays by atomic store. Returns tests per pair.
std::vector<std::uint32_t> PassIntersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                         std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                         const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                         std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded);

// The traversal passes with the node-sphere test as a parameter (the passes above use cone::Test;
// `rayspace accuracy` swaps in other precisions). test(node, sphere, eps) -> bool.
template <typename TestFn>
PairSlots TraverseTopWith(TestFn&& test, const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1,
                          std::uint32_t b0, std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres,
                          const SceneBuffers& scene, const std::vector<std::uint8_t>& object_mask, float eps) {
  const std::uint32_t T = b1 - b0;
  const std::size_t grid = static_cast<std::size_t>(t1 - t0) * T, objects = scene.objects.size();
  PairSlots s;
  s.flags.resize(grid);
  s.values.resize(grid);
  s.tested.resize(grid);
  ParallelFor(grid, [&](std::size_t e) {
    const std::uint32_t node = t0 + static_cast<std::uint32_t>(e / T), tri = b0 + static_cast<std::uint32_t>(e % T);
    const bool tested = object_mask.empty() || object_mask[static_cast<std::size_t>(node) * objects + scene.info[tri].ids.y];
    s.tested[e] = tested;
    s.flags[e] = tested && test(top[node], tri_spheres[tri], eps);
    s.values[e] = ((node - t0) << kPairTriangleBits) | (tri - b0);
  });
  return s;
}

template <typename TestFn>
std::vector<std::uint8_t> ObjectMaskWith(TestFn&& test, const std::vector<gpu::ConeNode>& top,
                                         const std::vector<glm::vec4>& object_spheres, float eps) {
  const std::size_t objects = object_spheres.size();
  std::vector<std::uint8_t> mask(top.size() * objects, 0);
  ParallelFor(mask.size(), [&](std::size_t e) { mask[e] = test(top[e / objects], object_spheres[e % objects], eps); });
  return mask;
}

template <typename TestFn>
PairSlots TraverseLevelWith(TestFn&& test, const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                            const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                            std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                            float eps) {
  PairSlots s;
  s.flags.assign(pairs.size() * children_max, 0);
  s.values.assign(pairs.size() * children_max, 0);
  s.tested.assign(pairs.size(), 0);
  ParallelFor(pairs.size(), [&](std::size_t p) {
    const std::uint32_t parent = base_up + (pairs[p] >> kPairTriangleBits), tri_local = pairs[p] & kPairTriangleMask;
    const glm::vec4 sphere = tri_spheres[b0 + tri_local];
    const std::uint32_t c0 = first[parent], c1 = first[parent + 1];
    s.tested[p] = static_cast<std::uint8_t>(c1 - c0);
    for (std::uint32_t c = c0; c < c1; ++c) {
      const std::size_t slot = p * children_max + (c - c0);
      s.flags[slot] = test(nodes[c], sphere, eps);
      s.values[slot] = ((c - base) << kPairTriangleBits) | tri_local;
    }
  });
  return s;
}

// Stream reduction of (flag, value) slots to the flagged values in slot order.
std::vector<std::uint32_t> ReduceScan(const std::vector<std::uint8_t>& flags, const std::vector<std::uint32_t>& values);
std::vector<std::uint32_t> ReduceHierarchical(const std::vector<std::uint8_t>& flags,
                                              const std::vector<std::uint32_t>& values, int component);

}  // namespace rayspace::emu
