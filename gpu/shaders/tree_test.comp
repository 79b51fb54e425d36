#version 460
// tree.test: every candidate of pair p tested into slots offsets[p] .. (flag 0 dropped, 1 goes on,
// 2 final, and the candidate pair), one invocation per pair; mirrors emu PassTreeTest.
#include "common.glsl"
#include "cone.glsl"
#include "tree.glsl"

void main() {
  const uint p = GlobalIndex();
  if (p >= pc.count) return;
  const uint cone = pair_cone[p], item = pair_item[p];
  const Expansion e = Expand(cone, item);
  const uint n = CountOf(e), nodes = e.cone_side ? n : e.k1 - e.k0;
  // Fault 2: each pair's candidates start one slot late.
  const uint at = offsets[p] + (kFault == 2u ? 1u : 0u);
  uint node_hits = 0u, tri_hits = 0u;
  for (uint k = 0u; k < n; ++k) {
    const uvec2 c = Candidate(e, cone, item, k);
    const bool hit = TestCandidate(c);
    if (k < nodes) node_hits += hit ? 1u : 0u;
    else tri_hits += hit ? 1u : 0u;
    if (at + k >= pc.slots) continue;
    // Fault 1: a final pair is flagged to go on.
    flags[at + k] = hit ? (kFault == 1u ? 1u : KindOf(c.x, c.y)) : 0u;
    out_cone[at + k] = c.x;
    out_item[at + k] = c.y;
  }
  // Fault 3: a hit is counted as a second test.
  const uint extra = kFault == 3u ? 1u : 0u;
  if (nodes > 0u) AddCounts(Candidate(e, cone, item, 0u), nodes + extra * node_hits, node_hits);
  if (n > nodes) AddCounts(Candidate(e, cone, item, nodes), (n - nodes) + extra * tri_hits, tri_hits);
}
