// The top level against the object tree (emu/object_tree_top.h): one top node per work item, a
// depth-first descent with an explicit stack, the reached triangles sorted and tested in order.
#include "rayspace/emu/object_tree_top.h"

#include <algorithm>

#include "rayspace/emu/cone.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

struct NodeResult {
  std::vector<std::uint32_t> pairs;
  std::uint64_t tri_tests = 0, node_tests = 0, node_hits = 0;
};

// The triangles of [b0, b1) below the object nodes top node `n`'s cone may meet, ascending.
std::vector<std::uint32_t> Reached(const call::TraverseTop& c, const ObjectTreeIndex& x, const layout::ConeNode& n, NodeResult& r) {
  std::vector<std::uint32_t> stack(x.tree.roots.rbegin(), x.tree.roots.rend()), found;
  while (!stack.empty()) {
    const std::uint32_t id = stack.back();
    stack.pop_back();
    if (x.hi[id] < c.b0 || x.lo[id] >= c.b1) continue;  // nothing of this batch below
    const ObjectTreeNode& node = x.tree.nodes[id];
    ++r.node_tests;
    if (!cone::Test(n, node.sphere, c.eps)) continue;
    ++r.node_hits;
    for (std::uint32_t k = 0; k < node.tris; ++k) {
      const std::uint32_t tri = x.tree.triangles[node.first_tri + k];
      if (tri >= c.b0 && tri < c.b1) found.push_back(tri);
    }
    for (std::uint32_t k = node.children; k-- > 0;) stack.push_back(node.first_child + k);
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

ObjectTreeIndex IndexObjectTree(ObjectTree tree) {
  ObjectTreeIndex x;
  const std::size_t n = tree.nodes.size();
  x.lo.assign(n, 0xffffffffu);
  x.hi.assign(n, 0);
  // Children follow their parents (breadth first), so a reverse sweep sees every child first.
  for (std::size_t i = n; i-- > 0;) {
    const ObjectTreeNode& node = tree.nodes[i];
    for (std::uint32_t k = 0; k < node.tris; ++k) {
      const std::uint32_t t = tree.triangles[node.first_tri + k];
      x.lo[i] = std::min(x.lo[i], t), x.hi[i] = std::max(x.hi[i], t);
    }
    for (std::uint32_t k = 0; k < node.children; ++k) {
      const std::uint32_t ch = node.first_child + k;
      RS_CHECK_MSG(ch > i, "object tree: child {} before its parent {}", ch, i);
      x.lo[i] = std::min(x.lo[i], x.lo[ch]), x.hi[i] = std::max(x.hi[i], x.hi[ch]);
    }
  }
  x.tree = std::move(tree);
  return x;
}

TreeTopResult TraverseTopTree(const call::TraverseTop& c, const ObjectTreeIndex& index) {
  std::vector<NodeResult> per(c.t1 - c.t0);
  ParallelForDynamic(per.size(), 16, [&](std::size_t i) {
    const std::uint32_t t = c.t0 + static_cast<std::uint32_t>(i);
    NodeResult& r = per[i];
    for (const std::uint32_t tri : Reached(c, index, c.top[t], r)) {
      ++r.tri_tests;
      if (cone::Test(c.top[t], c.tri_spheres[tri], c.eps))
        r.pairs.push_back((static_cast<std::uint32_t>(i) << layout::kPairTriangleBits) | (tri - c.b0));
    }
  });
  TreeTopResult out;
  for (NodeResult& r : per) {
    out.pairs.pairs.insert(out.pairs.pairs.end(), r.pairs.begin(), r.pairs.end());
    out.pairs.tested += r.tri_tests;
    out.node_tests += r.node_tests;
    out.node_hits += r.node_hits;
  }
  return out;
}

}  // namespace rayspace::emu
