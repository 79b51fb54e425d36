// The top level against the object tree (emu/object_tree_top.h): one top node per work item, a
// depth-first descent with an explicit stack (a node's children tested together on the lanes), the
// reached triangles tested in ascending order on the lanes: bit for bit the scalar cone::Test.
#include "rayspace/emu/object_tree_top.h"

#include <algorithm>
#include <bit>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

// A worker thread's buffers, reused from one top node to the next (no allocation per node once warm).
struct Scratch {
  std::vector<std::uint32_t> stack, buf, found, out;
  std::vector<std::uint64_t> marked;
  std::vector<glm::vec4> gathered;
};

struct NodeResult {
  std::vector<std::uint32_t> pairs;
  std::uint64_t tri_tests = 0, node_tests = 0, node_hits = 0;
};

bool Holds(const call::TraverseTop& c, const ObjectTreeIndex& x, std::uint32_t id) { return x.hi[id] >= c.b0 && x.lo[id] < c.b1; }

// The children of `node` that hold triangles of the batch and whose spheres the cone may meet, onto
// the stack: all of them at once on the lanes when every child holds some, else one by one.
void PushChildren(const call::TraverseTop& c, const ObjectTreeIndex& x, const layout::ConeNode& n, const ObjectTreeNode& node,
                  std::vector<std::uint32_t>& stack, std::vector<std::uint32_t>& buf, NodeResult& r) {
  const std::uint32_t k0 = node.first_child, k1 = node.first_child + node.children;
  bool all = true;
  for (std::uint32_t k = k0; k < k1 && all; ++k) all = Holds(c, x, k);
  if (all) {
    buf.resize(node.children + cone::kLanePad);
    const std::size_t m = cone::TestSpheres(FusedIsa(), n, x.lanes, k0, k1, c.eps, 0, 0, buf.data());
    r.node_tests += node.children, r.node_hits += m;
    stack.insert(stack.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(m));
    return;
  }
  for (std::uint32_t k = k0; k < k1; ++k) {
    if (!Holds(c, x, k)) continue;
    ++r.node_tests;
    if (!cone::Test(n, x.spheres[k], c.eps)) continue;
    ++r.node_hits;
    stack.push_back(k);
  }
}

// The triangles of [b0, b1) below the object nodes top node `n`'s cone may meet, ascending: marked in
// a bitmap of the batch while descending, read out in order (no sort).
// The result is z.found.
void Reached(const call::TraverseTop& c, const ObjectTreeIndex& x, const layout::ConeNode& n, Scratch& z, NodeResult& r) {
  std::vector<std::uint32_t>& stack = z.stack;
  std::vector<std::uint64_t>& marked = z.marked;
  stack.clear();
  z.found.clear();
  marked.assign((c.b1 - c.b0 + 63) / 64, 0);
  for (const std::uint32_t root : x.tree.roots) {
    if (!Holds(c, x, root)) continue;
    ++r.node_tests;
    if (!cone::Test(n, x.spheres[root], c.eps)) continue;
    ++r.node_hits;
    stack.push_back(root);
  }
  while (!stack.empty()) {  // every node on the stack passed its test
    const ObjectTreeNode& node = x.tree.nodes[stack.back()];
    stack.pop_back();
    for (std::uint32_t k = 0; k < node.tris; ++k) {
      const std::uint32_t tri = x.tree.triangles[node.first_tri + k];
      if (tri >= c.b0 && tri < c.b1) marked[(tri - c.b0) >> 6] |= std::uint64_t{1} << ((tri - c.b0) & 63);
    }
    PushChildren(c, x, n, node, stack, z.buf, r);
  }
  for (std::size_t w = 0; w < marked.size(); ++w)
    for (std::uint64_t m = marked[w]; m != 0; m &= m - 1)
      z.found.push_back(c.b0 + static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(std::countr_zero(m))));
}

// Top node t (item i of the block) against the reached triangles, on the lanes: their spheres
// gathered, the survivors' indices mapped back to batch-local triangles.
void TestReached(const call::TraverseTop& c, std::uint32_t i, Scratch& z, NodeResult& r) {
  const std::vector<std::uint32_t>& found = z.found;
  z.gathered.resize(found.size());
  for (std::size_t k = 0; k < found.size(); ++k) z.gathered[k] = c.tri_spheres[found[k]];
  const cone::SphereArrays lanes = cone::ToArrays(z.gathered);
  z.out.resize(found.size() + cone::kLanePad);
  const std::size_t m =
      cone::TestSpheres(FusedIsa(), c.top[c.t0 + i], lanes, 0, static_cast<std::uint32_t>(found.size()), c.eps, 0, 0, z.out.data());
  r.tri_tests += found.size();
  for (std::size_t k = 0; k < m; ++k) r.pairs.push_back((i << layout::kPairTriangleBits) | (found[z.out[k]] - c.b0));
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
  x.spheres.resize(n);
  for (std::size_t i = 0; i < n; ++i) x.spheres[i] = tree.nodes[i].sphere;
  x.lanes = cone::ToArrays(x.spheres);  // spans x.spheres' buffer, which moves with x
  x.tree = std::move(tree);
  return x;
}

TreeTopResult TraverseTopTree(const call::TraverseTop& c, const ObjectTreeIndex& index) {
  std::vector<NodeResult> per(c.t1 - c.t0);
  ParallelForDynamic(per.size(), 16, [&](std::size_t i) {
    thread_local Scratch z;
    NodeResult& r = per[i];
    Reached(c, index, c.top[c.t0 + i], z, r);
    TestReached(c, static_cast<std::uint32_t>(i), z, r);
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
