// `--objects tree`: the ray-space hierarchy and each object's bounding-sphere tree
// (rayspace/object_tree.h) descended together (docs/object-tree.md). A pair is (cone node, object
// item); each round refines every pair on one side, whichever is larger at the pair: the cone node
// into its children (a level-1 node into its rays), or the object node into its children and its
// own triangles. A pair of a level-1 node or a ray with a triangle is final: the rays below it are
// tested against the triangle.
//
// The rounds run as passes (tree.roots, then per round tree.expand, tree.test and two reductions)
// or fused (tree.step: test and compact in one pass); both give the same pairs in the same order:
// each pair's candidates in candidate order, pairs in pair order. The calls are in emu/calls.h, the
// buffers they read and write in emu/tree_streams.h.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/object_tree.h"

namespace rayspace::emu {

// The tree with its arrays (ObjectTreeView) and its node spheres as lane arrays (a node's children
// are consecutive: one multi-lane test) and its triangles' spheres in tree order (a node's own
// triangles are consecutive too).
struct ObjectTreeIndex {
  ObjectTreeIndex() = default;
  ObjectTreeIndex(ObjectTreeIndex&&) = default;  // moving keeps the vectors' buffers, which the lanes span
  ObjectTreeIndex& operator=(ObjectTreeIndex&&) = default;
  ObjectTreeIndex(const ObjectTreeIndex&) = delete;  // a copy's lanes would span the original's buffers
  ObjectTreeIndex& operator=(const ObjectTreeIndex&) = delete;
  ObjectTree tree;
  std::vector<glm::vec4> spheres;      // per node
  std::vector<glm::uvec4> links;       // per node: first child, children, first own triangle, own triangles
  std::vector<glm::vec4> tri_spheres;  // per entry of tree.triangles
  cone::SphereArrays lanes, tri_lanes;
  std::vector<LanesTriangle> tri_prepared;  // per entry of tree.triangles: the final tests' lanes
  ObjectTreeView View() const { return {spheres, links, tree.depth, tree.roots, tri_spheres, tree.triangles}; }
};
ObjectTreeIndex IndexObjectTree(ObjectTree tree, std::span<const glm::vec4> tri_spheres, std::span<const layout::Triangle> triangles);

// The ray-space hierarchy's levels in the arrays of ConeTreeView, and per level its nodes as lanes
// (for the fused step's host shortcut; or empty).
struct ConeTree {
  std::vector<layout::ConeNode> nodes;
  std::vector<std::uint32_t> base, first;
  std::vector<cone::NodeArrays> lanes;
  ConeTreeView View() const { return {nodes, base, first}; }
};
// Levels 0 (`rays`, one node per sorted ray) to D (`levels[D - 1]`) with their CSR child offsets
// (`first[L - 1]` for level L).
ConeTree MakeConeTree(std::span<const layout::ConeNode> rays, const std::vector<std::vector<layout::ConeNode>>& levels,
                      const std::vector<std::vector<std::uint32_t>>& first);

// Which side of a pair is refined: the cone when its cross-section where the object node's centre
// lies is wider than the node (radius + distance x tan(alpha) > the node's radius), or when it is
// at least a hemisphere. Multiplications, additions and comparisons only, each correctly rounded in
// Vulkan, but to nearest or toward zero as the device chooses: a decision on the boundary may go
// either way (the relaxed model asks through S = SpecReal; gpu/shaders/tree.glsl holds the kernel's).
template <typename S>
bool SplitConeOf(const layout::ConeNode& n, glm::vec4 o) {
  const S cosa(n.cone.w), sina(n.extra.x);
  if (!(cosa > S(0.0f))) return true;  // a hemisphere or wider: refining the object cannot narrow it
  // r + d tan(alpha) > R  <=>  d sin > (R - r) cos, squared when both sides are non-negative.
  const S rhs = (S(o.w) - S(n.sphere.w)) * cosa;
  if (rhs < S(0.0f)) return true;
  const S dx = S(o.x) - S(n.sphere.x), dy = S(o.y) - S(n.sphere.y), dz = S(o.z) - S(n.sphere.z);
  const S d2 = dx * dx + dy * dy + dz * dz;
  return d2 * (sina * sina) > rhs * rhs;
}
inline bool SplitCone(const layout::ConeNode& cone, glm::vec4 object_sphere) { return SplitConeOf<float>(cone, object_sphere); }

// A pair's candidates, in the order tree.expand counts them and tree.test and tree.step test them:
// the cone side's children [k0, k1) of `level`, or the object side's child nodes [k0, k1) then own
// triangles [t0, t1), tested against the cone at `level`. What the passes and the relaxed model
// (verify/) share.
struct TreeExpansion {
  bool cone_side = false;
  std::uint32_t level = 0, k0 = 0, k1 = 0, t0 = 0, t1 = 0;
  std::uint32_t Count() const { return (k1 - k0) + (t1 - t0); }
};
// The expansion of pair (cone, item): refining the cone side when `cone_side`, else the object side
// (the passes take SplitCone's decision; the relaxed model asks for both when it may go either way).
TreeExpansion ExpandTreePair(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, bool cone_side);
// Whether the passes refine the cone side of pair (cone, item) (a triangle item, or SplitCone).
bool TreeSplitsCone(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item);
// Candidate k of pair (cone, item) under e: its (cone, item).
std::pair<std::uint32_t, std::uint32_t> TreeCandidate(const TreeExpansion& e, std::uint32_t cone, std::uint32_t item, std::uint32_t k);
// What a candidate's cone-sphere test reads: the cone node, the item's sphere.
const layout::ConeNode& TreeConeNode(const ConeTreeView& cones, std::uint32_t cone);
glm::vec4 TreeItemSphere(const ObjectTreeView& tree, std::uint32_t item);
// A kept candidate's kind: 2 when it is final (a level-1 node or a ray with a triangle), else 1.
std::uint8_t TreePairKind(std::uint32_t cone, std::uint32_t item);
// Adds `tests` tests and `hits` hits of candidate (cone, item) to k (by cone level and object depth).
void CountTreeTests(TreeCounts& k, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, std::uint64_t tests,
                    std::uint64_t hits);
// Counts with every level and depth of the two trees, all zero.
TreeCounts EmptyTreeCounts(const ConeTreeView& cones, const ObjectTreeView& tree);

// The passes (emu/calls.h): tree.roots; a round as tree.expand, tree.test (after an exclusive scan
// of the counts) and the reductions; or fused as tree.step; the final tests.
TreeSlots PassTreeRoots(const call::TreeRoots& c);
std::vector<std::uint32_t> PassTreeExpand(const call::TreeExpand& c);
TreeSlots PassTreeTest(const call::TreeTest& c);
TreeRound PassTreeStep(const call::TreeStep& c);  // the scalar test, in blocks of pairs
std::vector<std::uint32_t> PassIntersectTree(const call::IntersectTree& c);  // per final pair: the rays tested
// The sorted rays [j0, j1) a final pair tests: a level-1 node's (first1 = its CSR offsets), or the ray.
std::pair<std::uint32_t, std::uint32_t> TreeFinalRays(std::span<const std::uint32_t> first1, std::uint32_t cone, std::uint32_t item);

// The fused path's host shortcuts: the same round on the SIMD lanes (FusedIsa()), and the final tests
// on the lanes with the batch's rays set up once.
struct ObjectTreeLanes {
  const std::vector<cone::NodeArrays>* cones = nullptr;  // per cone level
  const ObjectTreeIndex* tree = nullptr;
};
TreeRound PassTreeStepLanes(const call::TreeStep& c, const ObjectTreeLanes& lanes);
std::vector<std::uint32_t> PassIntersectTreeLanes(const call::IntersectTree& c, const WatertightArrays& w, const ObjectTreeIndex& tree);

// Test hooks, so that the tests that guard the descent can fail: the fused step drops the last
// survivor of every block; both paths refine an object node into all but its last child; the final
// tests test only the first ray of a level-1 node.
enum class TreeFault { kNone, kDropBlockSurvivor, kDropLastChild, kFirstRayOnly };
// Settings::tree_fault holds one of these (a test hook).

}  // namespace rayspace::emu
