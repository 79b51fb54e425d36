#version 460
// tree.step: one round of the joint descent fused with its compaction (mirrors emu PassTreeStep):
// the survivors of tree.test's slots, the pairs that go on and the final ones, each in slot order
// (pairs in pair order, a pair's candidates in candidate order). Blocks of kTreeStepBlock pairs, one
// workgroup each, in rounds of kLocalSize pairs, one an invocation (rayspace/contract.h):
//   kTreeStepPhaseCount    each block's survivors of both kinds (workgroup scans), and the counters
//   kTreeStepPhaseScan     one workgroup: exclusive scans of the block counts, the totals last
//   kTreeStepPhaseScatter  each block tests again and writes its survivors at its offsets plus the
//                          survivors of the invocations and rounds before (workgroup scans)
// offsets: next counts [0, blocks) then their total, final counts [blocks + 1, 2 blocks + 1) then
// theirs. The host sizes the outputs from the totals between the scan and the scatter.
#include "common.glsl"
#include "cone.glsl"
#include "tree.glsl"
#include "workgroup.glsl"

// Pair p's survivors of each kind.
uvec2 CountPair(uint p) {
  const uint cone = pair_cone[p], item = pair_item[p];
  const Expansion e = Expand(cone, item);
  const uint n = CountOf(e);
  uvec2 kinds = uvec2(0u);
  for (uint k = 0u; k < n; ++k) {
    const uvec2 c = Candidate(e, cone, item, k);
    if (TestCandidate(c)) kinds[KindOf(c.x, c.y) - 1u] += 1u;
  }
  return kinds;
}

// The same, adding the pair's tests and hits to the counters.
uvec2 CountPairAndTests(uint p) {
  const uint cone = pair_cone[p], item = pair_item[p];
  const Expansion e = Expand(cone, item);
  const uint n = CountOf(e), nodes = e.cone_side ? n : e.k1 - e.k0;
  uvec2 kinds = uvec2(0u);
  uint node_hits = 0u, tri_hits = 0u;
  for (uint k = 0u; k < n; ++k) {
    const uvec2 c = Candidate(e, cone, item, k);
    if (!TestCandidate(c)) continue;
    kinds[KindOf(c.x, c.y) - 1u] += 1u;
    if (k < nodes) ++node_hits;
    else ++tri_hits;
  }
  if (nodes > 0u) AddCounts(Candidate(e, cone, item, 0u), nodes, node_hits);
  if (n > nodes) AddCounts(Candidate(e, cone, item, nodes), n - nodes, tri_hits);
  return kinds;
}

// Writes pair p's survivors: kind 1 from output index at.x (block rank rank.x, of limit.x in the
// block), kind 2 from at.y.
void ScatterPair(uint p, uvec2 at, uvec2 rank, uvec2 limit) {
  const uint cone = pair_cone[p], item = pair_item[p];
  const Expansion e = Expand(cone, item);
  const uint n = CountOf(e), total = pc.slots + offsets[2u * pc.blocks + 1u];
  for (uint k = 0u; k < n; ++k) {
    const uvec2 c = Candidate(e, cone, item, k);
    if (!TestCandidate(c)) continue;
    const uint kind = KindOf(c.x, c.y) - 1u;
    if (rank[kind] < limit[kind] && at[kind] < total) {
      out_cone[at[kind]] = c.x;
      out_item[at[kind]] = c.y;
    }
    ++at[kind];
    ++rank[kind];
  }
}

void CountBlock(uint g) {
  const uint first = g * kTreeStepBlock, end = min(pc.count, first + kTreeStepBlock);
  uvec2 run = uvec2(0u);
  for (uint r0 = first; r0 < end; r0 += kLocalSize) {
    const uint p = r0 + gl_LocalInvocationID.x;
    const uvec2 n = p < end ? CountPairAndTests(p) : uvec2(0u);
    uint s1, s2;
    WorkgroupInclusiveAdd(n.x, s1);
    WorkgroupInclusiveAdd(n.y, s2);
    run += uvec2(s1, s2);
  }
  if (gl_LocalInvocationID.x == 0u) {
    // Fault 2: the last survivor of every block is dropped (of the pairs that go on).
    offsets[g] = kFault == 2u && run.x > 0u ? run.x - 1u : run.x;
    offsets[pc.blocks + 1u + g] = run.y;
  }
}

void ScatterBlock(uint g) {
  const uint first = g * kTreeStepBlock, end = min(pc.count, first + kTreeStepBlock);
  // Fault 1: the block's survivors land at the next block's offset. Fault 4: the final pairs start
  // one index early, over the last pair that goes on.
  const uvec2 base = kFault == 1u ? uvec2(offsets[g + 1u], pc.slots + offsets[pc.blocks + 2u + g])
                                  : uvec2(offsets[g], pc.slots - (kFault == 4u ? 1u : 0u) + offsets[pc.blocks + 1u + g]);
  const uvec2 limit = uvec2(offsets[g + 1u] - offsets[g], offsets[pc.blocks + 2u + g] - offsets[pc.blocks + 1u + g]);
  uvec2 run = uvec2(0u);
  const uint r = WorkgroupRank();
  for (uint r0 = first; r0 < end; r0 += kLocalSize) {
    const uint p = r0 + r;
    const uvec2 n = p < end ? CountPair(p) : uvec2(0u);
    uint s1, s2;
    const uvec2 before = uvec2(WorkgroupInclusiveAdd(n.x, s1), WorkgroupInclusiveAdd(n.y, s2)) - n;
    // Fault 3: every round starts at the block's start.
    const uvec2 rank = (kFault == 3u ? uvec2(0u) : run) + before;
    if (p < end) ScatterPair(p, base + rank, rank, limit);
    run += uvec2(s1, s2);
  }
}

void main() {
  const uint g = WorkGroupIndex();
  if (pc.phase == kTreeStepPhaseScan) {
    if (g != 0u) return;
    uint total;
    const uint rank = WorkgroupRank();  // once: both scans add in the same order
    WORKGROUP_SCAN_IN_PLACE(offsets, 0u, pc.blocks, rank, total);
    if (gl_LocalInvocationID.x == 0u) offsets[pc.blocks] = total;
    WORKGROUP_SCAN_IN_PLACE(offsets, pc.blocks + 1u, pc.blocks, rank, total);
    if (gl_LocalInvocationID.x == 0u) offsets[2u * pc.blocks + 1u] = total;
  } else if (g < pc.blocks) {  // uniform: the whole workgroup leaves
    if (pc.phase == kTreeStepPhaseCount)
      CountBlock(g);
    else
      ScatterBlock(g);
  }
}
