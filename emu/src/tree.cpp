// The joint descent of the ray-space hierarchy and the object tree (emu/object_tree_traverse.h): its
// passes one by one, the fused round (scalar and on the SIMD lanes) and the final tests.
#include "rayspace/emu/object_tree_traverse.h"

#include <algorithm>
#include <tuple>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {

using layout::kTreeItemTriangle;
using layout::kTreeLevelShift;
using layout::kTreeNodeMask;

TreeFault Fault() { return static_cast<TreeFault>(CurrentSettings().tree_fault); }

std::uint32_t LevelOf(std::uint32_t cone) { return cone >> kTreeLevelShift; }
std::uint32_t NodeOf(std::uint32_t cone) { return cone & kTreeNodeMask; }
std::uint32_t ConeOf(std::uint32_t level, std::uint32_t node) { return level << kTreeLevelShift | node; }
bool IsTriangle(std::uint32_t item) { return (item & kTreeItemTriangle) != 0; }

using Expansion = TreeExpansion;

// What every tree pass reads: the two hierarchies and the test margin.
struct Trees {
  const ConeTreeView& cones;
  const ObjectTreeView& tree;
  float eps;
};

bool SplitsCone(const Trees& c, std::uint32_t cone, std::uint32_t item) {
  const std::uint32_t L = LevelOf(cone);
  return IsTriangle(item) || (L > 0 && SplitCone(c.cones.Node(L, NodeOf(cone)), c.tree.tree_spheres[item]));
}

Expansion ExpandSide(const Trees& c, std::uint32_t cone, std::uint32_t item, bool cone_side) {
  const std::uint32_t L = LevelOf(cone), n = NodeOf(cone);
  RS_CHECK_MSG(!(IsTriangle(item) && L <= 1), "tree pair ({}, {}) is final, not one to refine", cone, item);
  RS_CHECK_MSG(!cone_side || L > 0, "tree pair ({}, {}): a ray has no children to refine into", cone, item);
  RS_CHECK_MSG(cone_side || !IsTriangle(item), "tree pair ({}, {}): a triangle has no children to refine into", cone, item);
  if (cone_side) return {true, L - 1, c.cones.First(L, n), c.cones.First(L, n + 1), 0, 0};
  const glm::uvec4 o = c.tree.tree_links[item];
  const std::uint32_t children = o.y - (Fault() == TreeFault::kDropLastChild && o.y > 0);
  return {false, L, o.x, o.x + children, o.z, o.z + o.w};
}

Expansion Expand(const Trees& c, std::uint32_t cone, std::uint32_t item) { return ExpandSide(c, cone, item, SplitsCone(c, cone, item)); }

// Candidate k of pair (cone, item) under expansion e.
std::pair<std::uint32_t, std::uint32_t> Candidate(const Expansion& e, std::uint32_t cone, std::uint32_t item, std::uint32_t k) {
  if (e.cone_side) return {ConeOf(e.level, e.k0 + k), item};
  const std::uint32_t nodes = e.k1 - e.k0;
  return {cone, k < nodes ? e.k0 + k : kTreeItemTriangle | (e.t0 + k - nodes)};
}

glm::vec4 SphereOf(const ObjectTreeView& x, std::uint32_t item) {
  return IsTriangle(item) ? x.tree_tri_spheres[item & ~kTreeItemTriangle] : x.tree_spheres[item];
}

bool TestCandidate(const Trees& c, std::uint32_t cone, std::uint32_t item) {
  return cone::Test(c.cones.Node(LevelOf(cone), NodeOf(cone)), SphereOf(c.tree, item), c.eps);
}

// The call the final tests record through (its pairs unused).
call::Intersect RecordTarget(const call::IntersectTree& c) {
  return {.pairs = {}, .first1 = {}, .base1 = 0, .b0 = 0, .order = c.order, .rays = c.rays, .scene = c.scene, .hits = c.hits,
          .occluded = c.occluded};
}

// 2 when the pair is final (a level-1 node or a ray with a triangle), else 1.
std::uint8_t KindOf(std::uint32_t cone, std::uint32_t item) { return IsTriangle(item) && LevelOf(cone) <= 1 ? 2 : 1; }

void Count(TreeCounts& k, const ObjectTreeView& x, std::uint32_t cone, std::uint32_t item, std::uint64_t tests, std::uint64_t hits) {
  k.cone_tests[LevelOf(cone)] += tests, k.cone_hits[LevelOf(cone)] += hits;
  if (IsTriangle(item)) {
    k.tri_tests += tests, k.tri_hits += hits;
  } else {
    k.node_tests[x.tree_depth[item]] += tests, k.node_hits[x.tree_depth[item]] += hits;
  }
}

TreeCounts EmptyCounts(const Trees& c) {
  TreeCounts k;
  std::uint32_t depths = 0;
  for (const std::uint32_t d : c.tree.tree_depth) depths = std::max(depths, d + 1);
  k.Resize(c.cones.Depth() + 1, depths);
  return k;
}

// Blocks of pairs whose candidates make about kFusedBlock slots (a pair has about eight).
constexpr std::size_t kPairsPerBlock = kFusedBlock / 8;

void Append(TreePairs& to, const TreePairs& from) {
  to.cone.insert(to.cone.end(), from.cone.begin(), from.cone.end());
  to.item.insert(to.item.end(), from.item.begin(), from.item.end());
}

// Runs block(p0, p1, round) over blocks of pairs in parallel and concatenates the blocks' rounds in
// block order (the pairs of a round are in pair order, each pair's candidates in candidate order).
template <typename BlockFn>
TreeRound InBlocks(const Trees& c, std::size_t n, BlockFn&& block) {
  const std::size_t blocks = (n + kPairsPerBlock - 1) / kPairsPerBlock;
  const TreeCounts empty = EmptyCounts(c);  // O(tree nodes): once per call, not per block
  std::vector<TreeRound> parts(blocks);
  ParallelForDynamic(blocks, 1, [&](std::size_t b) {
    TreeRound& r = parts[b];
    r.counts = empty;
    block(b * kPairsPerBlock, std::min(n, (b + 1) * kPairsPerBlock), r);
    if (Fault() == TreeFault::kDropBlockSurvivor && !r.next.cone.empty()) r.next.cone.pop_back(), r.next.item.pop_back();
  });
  TreeRound out;
  out.counts = empty;
  for (const TreeRound& r : parts) {
    Append(out.next, r.next);
    Append(out.final, r.final);
    out.counts.Add(r.counts);
  }
  return out;
}

void Push(TreeRound& r, std::uint32_t cone, std::uint32_t item) {
  TreePairs& to = KindOf(cone, item) == 2 ? r.final : r.next;
  to.cone.push_back(cone);
  to.item.push_back(item);
}

}  // namespace

void TreeCounts::Resize(int cone_levels, std::size_t node_depths) {
  cone_tests.assign(cone_levels, 0), cone_hits.assign(cone_levels, 0);
  node_tests.assign(node_depths, 0), node_hits.assign(node_depths, 0);
}

void TreeCounts::Add(const TreeCounts& o) {
  RS_CHECK(o.cone_tests.size() == cone_tests.size() && o.node_tests.size() == node_tests.size());
  for (std::size_t i = 0; i < cone_tests.size(); ++i) cone_tests[i] += o.cone_tests[i], cone_hits[i] += o.cone_hits[i];
  for (std::size_t i = 0; i < node_tests.size(); ++i) node_tests[i] += o.node_tests[i], node_hits[i] += o.node_hits[i];
  tri_tests += o.tri_tests, tri_hits += o.tri_hits;
}

ObjectTreeIndex IndexObjectTree(ObjectTree tree, std::span<const glm::vec4> tri_spheres, std::span<const layout::Triangle> triangles) {
  ObjectTreeIndex x;
  x.tri_prepared.resize(tree.triangles.size());
  ParallelFor(tree.triangles.size(), [&](std::size_t k) { x.tri_prepared[k] = PrepareLanesTriangle(triangles[tree.triangles[k]]); });
  x.spheres.resize(tree.nodes.size());
  x.links.resize(tree.nodes.size());
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const ObjectTreeNode& o = tree.nodes[i];
    x.spheres[i] = o.sphere;
    x.links[i] = glm::uvec4(o.first_child, o.children, o.first_tri, o.tris);
  }
  x.tri_spheres.resize(tree.triangles.size());
  for (std::size_t k = 0; k < tree.triangles.size(); ++k) x.tri_spheres[k] = tri_spheres[tree.triangles[k]];
  x.lanes = cone::ToArrays(x.spheres);  // span the vectors' buffers, which move with x
  x.tri_lanes = cone::ToArrays(x.tri_spheres);
  x.tree = std::move(tree);
  return x;
}

TreeExpansion ExpandTreePair(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, bool cone_side) {
  return ExpandSide(Trees{cones, tree, 0.0f}, cone, item, cone_side);
}
bool TreeSplitsCone(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item) {
  return SplitsCone(Trees{cones, tree, 0.0f}, cone, item);
}
std::pair<std::uint32_t, std::uint32_t> TreeCandidate(const TreeExpansion& e, std::uint32_t cone, std::uint32_t item, std::uint32_t k) {
  return Candidate(e, cone, item, k);
}
const layout::ConeNode& TreeConeNode(const ConeTreeView& cones, std::uint32_t cone) { return cones.Node(LevelOf(cone), NodeOf(cone)); }
glm::vec4 TreeItemSphere(const ObjectTreeView& tree, std::uint32_t item) { return SphereOf(tree, item); }
std::uint8_t TreePairKind(std::uint32_t cone, std::uint32_t item) { return KindOf(cone, item); }
void CountTreeTests(TreeCounts& k, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, std::uint64_t tests,
                    std::uint64_t hits) {
  Count(k, tree, cone, item, tests, hits);
}
TreeCounts EmptyTreeCounts(const ConeTreeView& cones, const ObjectTreeView& tree) { return EmptyCounts(Trees{cones, tree, 0.0f}); }

ConeTree MakeConeTree(std::span<const layout::ConeNode> rays, const std::vector<std::vector<layout::ConeNode>>& levels,
                      const std::vector<std::vector<std::uint32_t>>& first) {
  RS_CHECK(levels.size() == first.size());
  ConeTree t;
  t.nodes.assign(rays.begin(), rays.end());
  t.base = {0, static_cast<std::uint32_t>(rays.size())};
  for (std::uint32_t j = 0; j <= rays.size(); ++j) t.first.push_back(j);
  for (std::size_t L = 1; L <= levels.size(); ++L) {
    RS_CHECK(first[L - 1].size() == levels[L - 1].size() + 1);
    t.nodes.insert(t.nodes.end(), levels[L - 1].begin(), levels[L - 1].end());
    t.base.push_back(static_cast<std::uint32_t>(t.nodes.size()));
    t.first.insert(t.first.end(), first[L - 1].begin(), first[L - 1].end());
  }
  return t;
}

TreeSlots PassTreeRoots(const call::TreeRoots& c) {
  const Trees x{c.cones, c.tree, c.eps};
  const std::size_t roots = c.tree.tree_roots.size();
  TreeSlots s;
  s.counts = EmptyCounts(x);
  for (std::uint32_t t = c.t0; t < c.t1; ++t)
    for (const std::uint32_t root : c.tree.tree_roots) {
      const std::uint32_t cone = ConeOf(c.level, t);
      const bool hit = TestCandidate(x, cone, root);
      Count(s.counts, c.tree, cone, root, 1, hit);
      s.flags.push_back(hit ? KindOf(cone, root) : 0);
      s.pairs.cone.push_back(cone);
      s.pairs.item.push_back(root);
    }
  RS_CHECK(s.flags.size() == (c.t1 - c.t0) * roots);
  return s;
}

std::vector<std::uint32_t> PassTreeExpand(const call::TreeExpand& c) {
  const Trees x{c.cones, c.tree, 0.0f};
  std::vector<std::uint32_t> counts(c.pair_cone.size());
  ParallelFor(counts.size(), [&](std::size_t p) { counts[p] = Expand(x, c.pair_cone[p], c.pair_item[p]).Count(); });
  return counts;
}

TreeSlots PassTreeTest(const call::TreeTest& c) {
  const Trees x{c.cones, c.tree, c.eps};
  TreeSlots s;
  s.flags.assign(c.slots, 0);
  s.pairs.cone.assign(c.slots, 0);
  s.pairs.item.assign(c.slots, 0);
  const std::size_t n = c.pair_cone.size(), blocks = (n + kPairsPerBlock - 1) / kPairsPerBlock;
  const TreeCounts empty = EmptyCounts(x);
  std::vector<TreeCounts> counts(blocks, empty);
  ParallelForDynamic(blocks, 1, [&](std::size_t b) {
    for (std::size_t p = b * kPairsPerBlock; p < std::min(n, (b + 1) * kPairsPerBlock); ++p) {
      const std::uint32_t cone = c.pair_cone[p], item = c.pair_item[p];
      const Expansion e = Expand(x, cone, item);
      for (std::uint32_t k = 0; k < e.Count(); ++k) {
        const auto [kc, ki] = Candidate(e, cone, item, k);
        const bool hit = TestCandidate(x, kc, ki);
        Count(counts[b], c.tree, kc, ki, 1, hit);
        const std::size_t slot = c.offsets[p] + k;
        s.pairs.cone[slot] = kc, s.pairs.item[slot] = ki;
        s.flags[slot] = hit ? KindOf(kc, ki) : 0;
      }
    }
  });
  s.counts = empty;
  for (const TreeCounts& k : counts) s.counts.Add(k);
  return s;
}

TreeRound PassTreeStep(const call::TreeStep& c) {
  const Trees x{c.cones, c.tree, c.eps};
  return InBlocks(x, c.pair_cone.size(), [&](std::size_t p0, std::size_t p1, TreeRound& r) {
    for (std::size_t p = p0; p < p1; ++p) {
      const std::uint32_t cone = c.pair_cone[p], item = c.pair_item[p];
      const Expansion e = Expand(x, cone, item);
      for (std::uint32_t k = 0; k < e.Count(); ++k) {
        const auto [kc, ki] = Candidate(e, cone, item, k);
        const bool hit = TestCandidate(x, kc, ki);
        Count(r.counts, c.tree, kc, ki, 1, hit);
        if (hit) Push(r, kc, ki);
      }
    }
  });
}

TreeRound PassTreeStepLanes(const call::TreeStep& c, const ObjectTreeLanes& lanes) {
  const cone::Isa isa = FusedIsa();
  if (isa == cone::Isa::kScalar || !lanes.cones || !lanes.tree || lanes.cones->size() != static_cast<std::size_t>(c.cones.Depth() + 1))
    return PassTreeStep(c);
  const Trees x{c.cones, c.tree, c.eps};
  return InBlocks(x, c.pair_cone.size(), [&](std::size_t p0, std::size_t p1, TreeRound& r) {
    std::vector<std::uint32_t> buf;
    // Tests candidates [k0, k1) of one kind at once and pushes the survivors (indices into the range).
    auto run = [&](std::uint32_t k0, std::uint32_t k1, auto test, auto make) {
      if (k1 == k0) return;
      buf.resize(k1 - k0 + cone::kLanePad);
      const std::size_t m = test(k0, k1, buf.data());
      const auto [c0, i0] = make(k0);
      Count(r.counts, c.tree, c0, i0, k1 - k0, m);
      for (std::size_t q = 0; q < m; ++q) {
        const auto [kc, ki] = make(buf[q]);
        Push(r, kc, ki);
      }
    };
    for (std::size_t p = p0; p < p1; ++p) {
      const std::uint32_t cone = c.pair_cone[p], item = c.pair_item[p];
      const Expansion e = Expand(x, cone, item);
      if (e.cone_side) {
        const glm::vec4 s = SphereOf(c.tree, item);
        run(e.k0, e.k1,
            [&](std::uint32_t a, std::uint32_t b, std::uint32_t* out) { return cone::TestNodes(isa, (*lanes.cones)[e.level], s, a, b, c.eps, 0, 0, out); },
            [&](std::uint32_t k) { return std::pair{ConeOf(e.level, k), item}; });
        continue;
      }
      const layout::ConeNode& n = c.cones.Node(e.level, NodeOf(cone));
      run(e.k0, e.k1,
          [&](std::uint32_t a, std::uint32_t b, std::uint32_t* out) { return cone::TestSpheres(isa, n, lanes.tree->lanes, a, b, c.eps, 0, 0, out); },
          [&](std::uint32_t k) { return std::pair{cone, k}; });
      run(e.t0, e.t1,
          [&](std::uint32_t a, std::uint32_t b, std::uint32_t* out) { return cone::TestSpheres(isa, n, lanes.tree->tri_lanes, a, b, c.eps, 0, 0, out); },
          [&](std::uint32_t k) { return std::pair{cone, kTreeItemTriangle | k}; });
    }
  });
}

std::pair<std::uint32_t, std::uint32_t> TreeFinalRays(std::span<const std::uint32_t> first1, std::uint32_t cone, std::uint32_t item) {
  const std::uint32_t L = LevelOf(cone), n = NodeOf(cone);
  RS_CHECK_MSG(L <= 1 && IsTriangle(item), "tree pair ({}, {}) is not final", cone, item);
  const std::uint32_t j0 = L == 1 ? first1[n] : n;
  return {j0, L == 1 && Fault() != TreeFault::kFirstRayOnly ? first1[n + 1] : j0 + 1};
}

std::vector<std::uint32_t> PassIntersectTree(const call::IntersectTree& c) {
  const call::Intersect target = RecordTarget(c);
  std::vector<std::uint32_t> tests(c.pair_cone.size());
  ParallelFor(tests.size(), [&](std::size_t p) {
    const auto [j0, j1] = TreeFinalRays(c.first1, c.pair_cone[p], c.pair_item[p]);
    tests[p] = j1 - j0;
    IntersectRaysScalar(target, c.tree_triangles[c.pair_item[p] & ~kTreeItemTriangle], j0, j1);
  });
  return tests;
}

std::vector<std::uint32_t> PassIntersectTreeLanes(const call::IntersectTree& c, const WatertightArrays& w, const ObjectTreeIndex& tree) {
  const call::Intersect target = RecordTarget(c);
  const std::size_t n = c.pair_cone.size();
  std::vector<std::uint32_t> j0(n), j1(n), tests(n);
  ParallelFor(n, [&](std::size_t p) {
    std::tie(j0[p], j1[p]) = TreeFinalRays(c.first1, c.pair_cone[p], c.pair_item[p]);
    tests[p] = j1[p] - j0[p];
  });
  // Consecutive pairs of one triangle whose rays are adjacent (a node's children that all passed
  // against it) are one run of rays: the same tests in fuller lane groups.
  std::vector<std::size_t> runs;
  for (std::size_t p = 0; p < n; ++p)
    if (p == 0 || c.pair_item[p] != c.pair_item[p - 1] || j1[p - 1] != j0[p]) runs.push_back(p);
  runs.push_back(n);
  ParallelForDynamic(runs.size() - 1, 64, [&](std::size_t r) {
    const std::size_t a = runs[r], b = runs[r + 1] - 1;
    const std::uint32_t k = c.pair_item[a] & ~kTreeItemTriangle;
    IntersectRaysLanes(target, w, tree.tri_prepared[k], c.tree_triangles[k], j0[a], j1[b]);
  });
  return tests;
}


}  // namespace rayspace::emu
