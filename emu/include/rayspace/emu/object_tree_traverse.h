// `--objects tree`: the ray-space hierarchy and each object's bounding-sphere tree
// (rayspace/object_tree.h) descended together (docs/object-tree.md). A pair is (cone node, object
// item); each round refines every pair on one side, whichever is larger at the pair: the cone node
// into its children (a level-1 node into its rays), or the object node into its children and its
// own triangles. A pair of a level-1 node or a ray with a triangle is final: the rays below it are
// tested against the triangle.
//
// The rounds run as passes (tree.roots, then per round tree.expand, tree.test and two reductions)
// or fused (tree.step: test and compact in one pass); both give the same pairs in the same order:
// each pair's candidates in candidate order, pairs in pair order.
#pragma once
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/emu/streams.h"
#include "rayspace/object_tree.h"

namespace rayspace::emu {

// The tree with its node spheres as lane arrays (a node's children are consecutive: one multi-lane
// test) and its triangles' spheres in tree order (a node's own triangles are consecutive too).
struct ObjectTreeIndex {
  ObjectTreeIndex() = default;
  ObjectTreeIndex(ObjectTreeIndex&&) = default;  // moving keeps the vectors' buffers, which the lanes span
  ObjectTreeIndex& operator=(ObjectTreeIndex&&) = default;
  ObjectTreeIndex(const ObjectTreeIndex&) = delete;  // a copy's lanes would span the original's buffers
  ObjectTreeIndex& operator=(const ObjectTreeIndex&) = delete;
  ObjectTree tree;
  std::vector<glm::vec4> spheres;      // per node
  std::vector<glm::vec4> tri_spheres;  // per entry of tree.triangles
  cone::SphereArrays lanes, tri_lanes;
  std::vector<LanesTriangle> tri_prepared;  // per entry of tree.triangles: the final tests' lanes
};
ObjectTreeIndex IndexObjectTree(ObjectTree tree, std::span<const glm::vec4> tri_spheres, std::span<const layout::Triangle> triangles);

// A pair's two halves (rayspace/contract.h, kTree*): cone = level << kTreeLevelShift | node within
// its level (level 0: a ray, by its place in the sorted order); item = an object-tree node, or
// kTreeItemTriangle | an index into ObjectTree::triangles.
struct TreePairs {
  std::vector<std::uint32_t> cone, item;
  std::size_t size() const { return cone.size(); }
  RS_FIELDS(cone, item)
};

// The ray-space hierarchy as the descent reads it: nodes[L] for levels 0 (one node per sorted ray)
// to D; first[L] for L >= 1: the children of level-L node i are level L-1 nodes [first[L][i],
// first[L][i + 1]) (first[0] is empty).
struct ConeLevels {
  std::vector<std::span<const layout::ConeNode>> nodes;
  std::vector<std::span<const std::uint32_t>> first;
  std::vector<cone::NodeArrays> lanes;  // per level, for the fused step on the lanes (or empty)
  int Depth() const { return static_cast<int>(nodes.size()) - 1; }
};

// Tests and survivors of a round, by the level of the tested cone (0..D) and by the depth of the
// tested object node (tri: the tests against triangle spheres).
struct TreeCounts {
  std::vector<std::uint64_t> cone_tests, cone_hits;  // index: cone level
  std::vector<std::uint64_t> node_tests, node_hits;  // index: object-node depth
  std::uint64_t tri_tests = 0, tri_hits = 0;
  void Resize(int cone_levels, std::size_t node_depths);
  void Add(const TreeCounts& o);
  std::uint64_t Tests() const;
  bool operator==(const TreeCounts&) const = default;
};

// A round's output: the pairs that go on, the final pairs, and the counts.
struct TreeRound {
  TreePairs next, final;
  TreeCounts counts;
};

namespace call {

// Cone nodes [t0, t1) of `level` (the top level, or a lower one when one top node's pairs overflow)
// against every object's root sphere: the surviving (node, root) pairs.
struct TreeRoots {
  static constexpr std::string_view kName = "tree.roots";
  const ConeLevels* cones = nullptr;
  const ObjectTreeIndex* tree = nullptr;
  std::uint32_t level = 0, t0 = 0, t1 = 0;
  float eps = 0.0f;
};

// One round over `pairs`.
struct TreeStep {
  static constexpr std::string_view kName = "tree.step";
  const ConeLevels* cones = nullptr;
  const ObjectTreeIndex* tree = nullptr;
  const TreePairs* pairs = nullptr;
  float eps = 0.0f;
};

// The final tests: each pair's rays (a level-1 node's, or the one ray) against its triangle; closest
// hits by atomic minimum into `hits`, or occlusion flags into `occluded`.
struct IntersectTree {
  static constexpr std::string_view kName = "intersect.tree";
  const TreePairs* pairs = nullptr;
  std::span<const std::uint32_t> first1;  // ConeLevels::first[1]
  const ObjectTreeIndex* tree = nullptr;
  std::span<const std::uint32_t> order;
  std::span<const layout::Ray> rays;
  const SceneBuffers* scene = nullptr;
  std::vector<std::uint64_t>* hits = nullptr;
  std::vector<std::uint32_t>* occluded = nullptr;
};

}  // namespace call

// Which side of a pair is refined: the cone when its cross-section where the object node's centre
// lies is wider than the node (radius + distance x tan(alpha) > the node's radius), or when it is
// at least a hemisphere; multiplications and additions only, so every device decides alike.
bool SplitCone(const layout::ConeNode& cone, glm::vec4 object_sphere);

// The passes: tree.roots; a round as tree.expand (per pair: its candidates, 0 when there are none),
// tree.test (per candidate slot, after an exclusive scan of the counts: 0 dropped, 1 goes on,
// 2 final, and the slot's pair), and the reductions; or fused as tree.step.
TreeRound PassTreeRoots(const call::TreeRoots& c);
std::vector<std::uint32_t> PassTreeExpand(const call::TreeStep& c);
struct TreeSlots {
  std::vector<std::uint8_t> flags;  // 0 dropped, 1 next, 2 final
  TreePairs pairs;
  TreeCounts counts;
};
TreeSlots PassTreeTest(const call::TreeStep& c, std::span<const std::uint32_t> offsets, std::size_t slots);
TreeRound PassTreeStep(const call::TreeStep& c);      // the scalar test, in blocks of pairs
TreeRound PassTreeStepLanes(const call::TreeStep& c); // the same on the SIMD lanes (FusedIsa())
std::vector<std::uint32_t> PassIntersectTree(const call::IntersectTree& c);  // per final pair: the rays tested
// The same on the lanes, with the batch's rays set up once (the fused path's host shortcut).
std::vector<std::uint32_t> PassIntersectTreeLanes(const call::IntersectTree& c, const WatertightArrays& w);

// Test hooks, so that the tests that guard the descent can fail: the fused step drops the last
// survivor of every block; both paths refine an object node into all but its last child; the final
// tests test only the first ray of a level-1 node.
enum class TreeFault { kNone, kDropBlockSurvivor, kDropLastChild, kFirstRayOnly };
void SetTreeFaultForTesting(TreeFault fault);

}  // namespace rayspace::emu
