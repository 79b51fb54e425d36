// The contract of the tree passes' inputs (emu/calls.h, `--objects tree`), checked before a saved or
// hand-made call runs: a call that passes runs on every backend without reading out of bounds.
#include <algorithm>

#include "rayspace/contract.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

using layout::kTreeItemTriangle;
using layout::kTreeLevelShift;
using layout::kTreeNodeMask;

void CheckCsr(std::string_view call, const char* what, std::span<const std::uint32_t> f, std::size_t items) {
  if (f.empty() || f.front() != 0 || f.back() != items) ThrowInput("{}: input '{}' must run from 0 to {}", call, what, items);
  for (std::size_t i = 1; i < f.size(); ++i)
    if (f[i] < f[i - 1]) ThrowInput("{}: input '{}' decreases at {}", call, what, i);
}

void CheckCones(std::string_view call, const ConeTreeView& c) {
  const std::span<const std::uint32_t> b = c.cone_base;
  if (b.size() < 3 || b.size() > 16 || b.front() != 0 || b.back() != c.cone_nodes.size())
    ThrowInput("{}: input 'cone_base' must hold 3 to 16 level starts from 0 to {}", call, c.cone_nodes.size());
  for (std::size_t L = 1; L < b.size(); ++L)
    if (b[L] < b[L - 1] || b[L] - b[L - 1] > kTreeNodeMask) ThrowInput("{}: input 'cone_base' is out of order at {}", call, L);
  if (c.cone_first.size() != c.cone_nodes.size() + b.size() - 1)
    ThrowInput("{}: input 'cone_first' holds {} words, not nodes + levels = {}", call, c.cone_first.size(), c.cone_nodes.size() + b.size() - 1);
  for (std::uint32_t L = 1; L + 1 < b.size(); ++L) CheckCsr(call, "cone_first", c.FirstOf(L), c.Count(L - 1));
}

void CheckTree(std::string_view call, const ObjectTreeView& t) {
  const std::size_t nodes = t.tree_spheres.size(), tris = t.tree_triangles.size();
  if (t.tree_links.size() != nodes || t.tree_depth.size() != nodes || t.tree_tri_spheres.size() != tris)
    ThrowInput("{}: the object tree's arrays differ in length", call);
  if (nodes >= kTreeItemTriangle || tris >= kTreeItemTriangle) ThrowInput("{}: the object tree is too large", call);
  for (std::size_t i = 0; i < nodes; ++i) {
    const glm::uvec4 l = t.tree_links[i];
    if (std::uint64_t{l.x} + l.y > nodes || std::uint64_t{l.z} + l.w > tris || t.tree_depth[i] > 64)
      ThrowInput("{}: input 'tree_links' element {} is out of range", call, i);
  }
  for (std::size_t i = 0; i < t.tree_roots.size(); ++i)
    if (t.tree_roots[i] >= nodes) ThrowInput("{}: input 'tree_roots' element {} is out of range", call, i);
}

// Every pair names a node of its level and an object item; `final` pairs are final (a level-1 node
// or a ray with a triangle), the others are not.
void CheckPairs(std::string_view call, const ConeTreeView& c, const ObjectTreeView& t, In<std::uint32_t> cone, In<std::uint32_t> item,
                bool final) {
  if (cone.size() != item.size()) ThrowInput("{}: inputs 'pair_cone' and 'pair_item' differ in length", call);
  for (std::size_t p = 0; p < cone.size(); ++p) {
    const std::uint32_t L = cone[p] >> kTreeLevelShift, n = cone[p] & kTreeNodeMask, k = item[p] & ~kTreeItemTriangle;
    const bool tri = (item[p] & kTreeItemTriangle) != 0;
    if (L > static_cast<std::uint32_t>(c.Depth()) || n >= c.Count(L) || k >= (tri ? t.tree_triangles.size() : t.tree_spheres.size()) ||
        (tri && L <= 1) != final)
      ThrowInput("{}: pair {} ({}, {}) is out of range or {}", call, p, cone[p], item[p], final ? "not final" : "final");
  }
}

}  // namespace

void CheckInputs(const call::TreeRoots& c) {
  CheckCones(c.kName, c.cones);
  CheckTree(c.kName, c.tree);
  if (c.level > static_cast<std::uint32_t>(c.cones.Depth()) || c.t0 > c.t1 || c.t1 > c.cones.Count(c.level))
    ThrowInput("{}: nodes [{}, {}) of level {} are out of range", c.kName, c.t0, c.t1, c.level);
  if (std::uint64_t{c.t1 - c.t0} * c.tree.tree_roots.size() >= (std::uint64_t{1} << 32))
    ThrowInput("{}: {} nodes x {} roots exceed 2^32 slots", c.kName, c.t1 - c.t0, c.tree.tree_roots.size());
}

void CheckInputs(const call::TreeExpand& c) {
  CheckCones(c.kName, c.cones);
  CheckTree(c.kName, c.tree);
  CheckPairs(c.kName, c.cones, c.tree, c.pair_cone, c.pair_item, false);
}

void CheckInputs(const call::TreeStep& c) {
  CheckCones(c.kName, c.cones);
  CheckTree(c.kName, c.tree);
  CheckPairs(c.kName, c.cones, c.tree, c.pair_cone, c.pair_item, false);
}

void CheckInputs(const call::TreeTest& c) {
  CheckCones(c.kName, c.cones);
  CheckTree(c.kName, c.tree);
  CheckPairs(c.kName, c.cones, c.tree, c.pair_cone, c.pair_item, false);
  if (c.offsets.size() != c.pair_cone.size()) ThrowInput("{}: input 'offsets' holds {} words, not one per pair", c.kName, c.offsets.size());
  // The offsets must be the exclusive scan of the candidate counts: each pair's slots inside [0, slots)
  // and after the pair before's.
  const std::vector<std::uint32_t> counts = PassTreeExpand({.cones = c.cones, .tree = c.tree, .pair_cone = c.pair_cone, .pair_item = c.pair_item});
  std::uint64_t at = 0;
  for (std::size_t p = 0; p < counts.size(); ++p) {
    if (c.offsets[p] != at) ThrowInput("{}: input 'offsets' element {} is {}, not the scan of the candidate counts ({})", c.kName, p, c.offsets[p], at);
    at += counts[p];
  }
  if (at != c.slots) ThrowInput("{}: scalar 'slots' = {} is not the candidates' total {}", c.kName, c.slots, at);
}

void CheckInputs(const call::IntersectTree& c) {
  if (!c.scene) ThrowInput("{}: the call has no scene", c.kName);
  for (std::size_t i = 0; i < c.order.size(); ++i)
    if (c.order[i] >= c.rays.size()) ThrowInput("{}: input 'order' element {} is out of range", c.kName, i);
  CheckCsr(c.kName, "first1", c.first1, c.order.size());
  for (std::size_t i = 0; i < c.tree_triangles.size(); ++i)
    if (c.tree_triangles[i] >= c.scene->triangles.size()) ThrowInput("{}: input 'tree_triangles' element {} is out of range", c.kName, i);
  if (c.pair_cone.size() != c.pair_item.size()) ThrowInput("{}: inputs 'pair_cone' and 'pair_item' differ in length", c.kName);
  for (std::size_t p = 0; p < c.pair_cone.size(); ++p) {
    const std::uint32_t L = c.pair_cone[p] >> kTreeLevelShift, n = c.pair_cone[p] & kTreeNodeMask;
    const std::uint32_t k = c.pair_item[p] & ~kTreeItemTriangle;
    if (L > 1 || (c.pair_item[p] & kTreeItemTriangle) == 0 || k >= c.tree_triangles.size() ||
        n >= (L == 1 ? c.first1.size() - 1 : c.order.size()))
      ThrowInput("{}: pair {} ({}, {}) is out of range or not final", c.kName, p, c.pair_cone[p], c.pair_item[p]);
  }
  if ((c.hits == nullptr) == (c.occluded == nullptr)) ThrowInput("{}: exactly one of 'hits' and 'occluded' is needed", c.kName);
  const std::size_t n = c.hits ? c.hits->size() : c.occluded->size();
  if (n != c.rays.size()) ThrowInput("{}: '{}' holds {} entries, not one per ray ({})", c.kName, c.hits ? "hits" : "occluded", n, c.rays.size());
}

}  // namespace rayspace::emu
