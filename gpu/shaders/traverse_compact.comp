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

// Top-level slot s: top node t0 + s / tris against triangle b0 + s % tris, traverse.comp's numbering,
// packing and object-mask rule. Returns whether the test runs; `hit`: the pair survives.
bool TopSlot(uint s, out bool hit, out uint value) {
  const uint node = pc.t0 + s / pc.tris, tri = pc.b0 + s % pc.tris;
  value = ((node - pc.id_base) << kPairTriangleBits) | (tri - pc.b0);
  const bool test = pc.use_mask == 0u || object_mask[(node - pc.t0) * pc.objects + info[tri].ids.y] != 0u;
  hit = test && ConeTest(LoadNodes(node, pc.node_page), tri_spheres[tri], pc.eps);
  return test;
}

// Lower-level slot s: child s % children_max of the node of pair s / children_max; a slot past the
// node's children runs no test.
bool LevelSlot(uint s, out bool hit, out uint value) {
  const uint p = s / pc.children_max, k = s - p * pc.children_max;
  const uint parent = pc.base_up + (pairs[p] >> kPairTriangleBits), tri_local = pairs[p] & kPairTriangleMask;
  const uint c = LoadFirst(parent, pc.first_page) + k;
  hit = false;
  value = 0u;
  if (c >= LoadFirst(parent + 1u, pc.first_page)) return false;
  value = ((c - pc.base) << kPairTriangleBits) | tri_local;
  hit = ConeTest(LoadNodes(c, pc.node_page), tri_spheres[pc.b0 + tri_local], pc.eps);
  return true;
}

// Phase A for block g (uniform control flow: every invocation runs every round).
void TestBlock(uint g) {
  const uint first = g * kCompactBlock, end = min(pc.count, first + kCompactBlock), l = gl_LocalInvocationID.x;
  uint run = 0u, tests = 0u;  // survivors and tests of the rounds before
  for (uint r0 = first; r0 < end; r0 += kLocalSize * kCompactRun) {
    uint kept[kCompactRun];
    uint n = 0u, t = 0u;
    const uint s0 = r0 + l * kCompactRun;
    for (uint k = 0u; k < kCompactRun && s0 + k < end; ++k) {
      bool hit;
      uint value;
      const bool ran = pc.phase == kTraverseCompactPhaseTop ? TopSlot(s0 + k, hit, value) : LevelSlot(s0 + k, hit, value);
      t += ran ? 1u : 0u;
      if (hit) kept[n++] = value;
    }
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
