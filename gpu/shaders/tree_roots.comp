#version 460
// tree.roots: cone nodes t0 .. of `level` against every object's root sphere, one invocation per
// slot (node, root) in that order; mirrors emu PassTreeRoots.
#include "common.glsl"
#include "cone.glsl"
#include "tree.glsl"

void main() {
  const uint e = GlobalIndex();
  if (e >= pc.count) return;
  const uint nodes = pc.count / pc.roots;
  // Fault 2: node and root taken in the other order.
  const uint t = kFault == 2u ? e % nodes : e / pc.roots, r = kFault == 2u ? e / nodes : e % pc.roots;
  const uvec2 c = uvec2(ConeOf(pc.level, pc.t0 + t), tree_roots[r]);
  // Fault 1: the last root is never tested.
  const bool hit = !(kFault == 1u && r == pc.roots - 1u) && TestCandidate(c);
  flags[e] = hit ? KindOf(c.x, c.y) : 0u;
  out_cone[e] = c.x;
  out_item[e] = c.y;
  // Fault 3: a hit is counted as a second test.
  AddCounts(c, kFault == 3u && hit ? 2u : 1u, hit ? 1u : 0u);
}
