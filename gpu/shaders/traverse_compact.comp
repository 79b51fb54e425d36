#version 460
// The traversal fused with its stream reduction (mirrors emu PassTraverseTopCompacted /
// PassTraverseLevelCompacted): the survivors of traverse.comp's slots, in slot order, without the
// flag and value arrays and the separate reduce pass. Three dispatches (rayspace/contract.h):
//   kTraverseCompactPhaseTop / Level  one workgroup per block of kCompactBlock slots, in rounds of
//       kLocalSize x kCompactRun slots: each invocation tests kCompactRun consecutive slots and keeps
//       its survivors; one workgroup scan of (survivors, tests) places them after the survivors of
//       the invocations and rounds before, in the block's region of the scratch buffer
//   kTraverseCompactPhaseScan      one workgroup: exclusive scan of the block counts, sum of the tests
//   kTraverseCompactPhaseScatter   one workgroup per block copies its survivors to its offset
// Slot order follows: within a round from the invocations' consecutive runs and the scan, across
// rounds from the carry, across blocks from the scan. Reduce-then-scan, no decoupled look-back:
// look-back needs forward progress between workgroups, which lavapipe does not promise.
#include "common.glsl"
#include "cone.glsl"
#include "paged.glsl"
#include "workgroup.glsl"

layout(std430, binding = kTraverseCompactBindTriSpheres) readonly buffer TriSpheres { vec4 tri_spheres[]; };
layout(std430, binding = kTraverseCompactBindInfo) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = kTraverseCompactBindMask) readonly buffer Mask { uint object_mask[]; };
layout(std430, binding = kTraverseCompactBindPairs) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = kTraverseCompactBindScratch) buffer Scratch { uint scratch[]; };
layout(std430, binding = kTraverseCompactBindCounts) buffer Counts { uint counts[]; };  // blocks + 1
layout(std430, binding = kTraverseCompactBindTested) buffer Tested { uint tested[]; };  // blocks + 1
layout(std430, binding = kTraverseCompactBindOut) writeonly buffer Out { uint out_pairs[]; };
PAGED_BUFFER(readonly, Nodes, ConeNode, kTraverseCompactBindNodes)
PAGED_LOAD(Nodes, ConeNode)
PAGED_BUFFER(readonly, First, uint, kTraverseCompactBindFirst)
PAGED_LOAD(First, uint)
layout(push_constant) uniform Block { TraverseCompactPush pc; };

// The survivors of the invocation's slots in the current round, in slot order (private memory).
uint kept[kCompactRun];

// Phase A's tests of top-level slots [s0, s1): slot (row, col) is top node t0 + row against triangle
// b0 + col, row-major, with traverse.comp's packing and object-mask rule. The slots are consecutive,
// so the column steps instead of a division per slot, and a row's node is fetched once. Returns the
// survivors (in kept); `tests` receives the tests run.
uint TestTopSlots(uint s0, uint s1, out uint tests) {
  uint row = s0 / pc.tris, col = s0 - row * pc.tris, n = 0u;
  ConeNode node = LoadNodes(pc.t0 + row, pc.node_page);
  tests = 0u;
  for (uint s = s0; s < s1; ++s) {
    const uint tri = pc.b0 + col;
    if (pc.use_mask == 0u || object_mask[row * pc.objects + info[tri].ids.y] != 0u) {
      ++tests;
      if (ConeTest(node, tri_spheres[tri], pc.eps)) kept[n++] = ((pc.t0 + row - pc.id_base) << kPairTriangleBits) | col;
    }
    if (++col == pc.tris && s + 1u < s1) {
      col = 0u;
      ++row;
      node = LoadNodes(pc.t0 + row, pc.node_page);
    }
  }
  return n;
}

// Phase A's tests of lower-level slots [s0, s1): slot (p, k) is child k of the node of pair p,
// p * children_max + k as in traverse.comp. Only slots that hold a child are visited: a pair's node
// has fewer children than children_max, and the lanes of a SIMD device would otherwise idle through
// the empty slots. Returns the survivors (in kept); `tests` receives the tests run.
uint TestLevelSlots(uint s0, uint s1, out uint tests) {
  uint n = 0u;
  tests = 0u;
  for (uint p = s0 / pc.children_max; p * pc.children_max < s1; ++p) {
    const uint parent = pc.base_up + (pairs[p] >> kPairTriangleBits), tri_local = pairs[p] & kPairTriangleMask;
    const uint c0 = LoadFirst(parent, pc.first_page), c1 = LoadFirst(parent + 1u, pc.first_page);
    const uint row0 = p * pc.children_max, k1 = min(min(s1, row0 + pc.children_max) - row0, c1 - c0);
    const vec4 sphere = tri_spheres[pc.b0 + tri_local];
    for (uint k = max(s0, row0) - row0; k < k1; ++k) {
      ++tests;
      if (ConeTest(LoadNodes(c0 + k, pc.node_page), sphere, pc.eps)) kept[n++] = ((c0 + k - pc.base) << kPairTriangleBits) | tri_local;
    }
  }
  return n;
}

// Phase A for block g (uniform control flow: every invocation runs every round).
void TestBlock(uint g) {
  const uint first = g * kCompactBlock, end = min(pc.count, first + kCompactBlock), l = gl_LocalInvocationID.x;
  uint run = 0u, tests = 0u;  // survivors and tests of the rounds before
  for (uint r0 = first; r0 < end; r0 += kLocalSize * kCompactRun) {
    const uint s0 = min(r0 + l * kCompactRun, end), s1 = min(s0 + kCompactRun, end);
    uint t = 0u, n = 0u;
    if (s0 < s1) n = pc.phase == kTraverseCompactPhaseTop ? TestTopSlots(s0, s1, t) : TestLevelSlots(s0, s1, t);
    // One scan for both counts, 16 bits each: a round has at most kMaxLocalSize x kCompactRun < 2^16.
    uint sums;
    const uint before = (WorkgroupInclusiveAdd(n | (t << 16), sums) & 0xFFFFu) - n;
    // Fault 3: every round starts at the block's start (the carry between rounds is dropped).
    const uint at = first + (kFault == 3u ? 0u : run) + before;
    for (uint j = 0u; j < n; ++j) scratch[at + j] = kept[j];
    run += sums & 0xFFFFu;
    tests += sums >> 16;
  }
  if (l == 0u) {
    // Fault 2: the last survivor of every block is dropped. Fault 4: the survivors reported as tests.
    counts[g] = (kFault == 2u && run > 0u) ? run - 1u : run;
    tested[g] = kFault == 4u ? run : tests;
  }
}

// Phase C for block g: its survivors from the scratch region to its offset.
void ScatterBlock(uint g) {
  const uint at = counts[g], n = counts[g + 1u] - at;
  // Fault 1: the block lands at the next block's offset (the scan read as inclusive).
  const uint dst = kFault == 1u ? counts[g + 1u] : at;
  for (uint k = gl_LocalInvocationID.x; k < n; k += kLocalSize)
    if (dst + k < pc.count) out_pairs[dst + k] = scratch[g * kCompactBlock + k];  // the bound holds but for fault 1
}

void main() {
  const uint g = WorkGroupIndex();
  if (pc.phase == kTraverseCompactPhaseScan) {
    if (g != 0u) return;
    uint total;
    WORKGROUP_SCAN_IN_PLACE(counts, 0u, pc.blocks, total);
    if (gl_LocalInvocationID.x == 0u) counts[pc.blocks] = total;
    WORKGROUP_SUM(tested, 0u, pc.blocks, total);
    if (gl_LocalInvocationID.x == 0u) tested[pc.blocks] = total;
  } else if (g < pc.blocks) {  // uniform: the whole workgroup leaves
    if (pc.phase == kTraverseCompactPhaseScatter)
      ScatterBlock(g);
    else
      TestBlock(g);
  }
}
