#version 460
// Stream reduction of (flag, value) slots to the flagged values in slot order, as workgroup kernels;
// mirrors emu ReduceHierarchical and ReduceScan.
//   Roger et al.'s hierarchical reduction:
//     Local      one subgroup per component of s slots compacts it in slot order (subgroup scans of the
//                flags, no barrier) and counts it
//     BlockSums  one workgroup per block of kScanBlock counts sums them
//     ScanSums   one workgroup scans the block sums, kLocalSize at a time with a running carry
//     Offsets    one workgroup per block turns its counts into exclusive offsets
//     Concat     one subgroup per component copies its segment to its offset, a lane per element
//   Not a workgroup per component: scanning a component's flags with barriers made the reduction ten
//   times slower on lavapipe, whose barriers are costly.
//   Scan-based: FlagSums (block sums of the flags), ScanSums, Scatter (per block, a workgroup scan of
//   the flags places each flagged value), the order-preserving compaction of trim.comp.
// Reduce-then-scan rather than decoupled look-back: lavapipe does not promise forward progress
// between workgroups.
#include "common.glsl"
#include "workgroup.glsl"

layout(std430, binding = kReduceBindFlags) readonly buffer Flags { uint flags[]; };
layout(std430, binding = kReduceBindValues) readonly buffer Values { uint values[]; };
layout(std430, binding = kReduceBindLocal) buffer Local { uint local_values[]; };
layout(std430, binding = kReduceBindCounts) buffer Counts { uint counts[]; };   // per component, then exclusive offsets
layout(std430, binding = kReduceBindSums) buffer Sums { uint sums[]; };       // per block of kScanBlock counts, plus total
layout(std430, binding = kReduceBindOut) writeonly buffer Out { uint out_values[]; };
layout(push_constant) uniform Block { ReducePush pc; };

void main() {
  const uint g = WorkGroupIndex(), l = gl_LocalInvocationID.x;
  uint total;
  if (pc.phase == kReducePhaseFlagSums) {
    if (g >= pc.blocks) return;  // uniform: the whole workgroup leaves
    WORKGROUP_SUM(flags, g * kScanBlock, min(pc.n, (g + 1u) * kScanBlock), total);
    if (l == 0u) sums[g] = total;
  } else if (pc.phase == kReducePhaseScatter) {  // after ScanSums scanned the block sums
    if (g >= pc.blocks) return;
    // Fault 2: each block starts at the previous block's offset (an off-by-one in the scan).
    uint run = (kFault == 2u && g > 0u) ? sums[g - 1u] : sums[g];
    const uint end = min(pc.n, (g + 1u) * kScanBlock), r = WorkgroupRank();
    for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
      const uint i = c0 + r;
      const uint f = i < end && flags[i] != 0u ? 1u : 0u;
      const uint at = run + (WorkgroupInclusiveAdd(f, total) - f);
      if (f != 0u) out_values[at] = values[i];
      run += total;
    }
  } else if (pc.phase == kReducePhaseLocal) {
    // One subgroup per component, grid-stride over the components: each chunk of `lanes` slots is
    // compacted by a subgroup exclusive add of the flags (no barrier), in slot order: lanes are
    // ranked among the active ones, and a workgroup takes SubgroupSlots() components whatever
    // subgroups the device launched (any past them idle).
    const uint lanes = subgroupBallotBitCount(subgroupBallot(true)), lane = subgroupBallotExclusiveBitCount(subgroupBallot(true));
    const uint slots = SubgroupSlots(), stride = gl_NumWorkGroups.x * gl_NumWorkGroups.y * slots;
    for (uint c = g * slots + gl_SubgroupID; gl_SubgroupID < slots && c < pc.comps; c += stride) {
      const uint base = c * pc.s, end = min(pc.n, base + pc.s);
      uint k = 0u;
      for (uint c0 = base; c0 < end; c0 += lanes) {
        const uint i = c0 + lane;
        const uint f = i < end && flags[i] != 0u ? 1u : 0u;
        const uint at = k + subgroupExclusiveAdd(f);
        if (f != 0u) local_values[base + at] = values[i];
        k += subgroupAdd(f);
      }
      if (subgroupElect()) counts[c] = k;
    }
  } else if (pc.phase == kReducePhaseBlockSums) {
    if (g >= pc.blocks) return;
    WORKGROUP_SUM(counts, g * kScanBlock, min(pc.comps, (g + 1u) * kScanBlock), total);
    if (l == 0u) sums[g] = total;
  } else if (pc.phase == kReducePhaseScanSums) {
    if (g != 0u) return;
    WORKGROUP_SCAN_IN_PLACE(sums, 0u, pc.blocks, WorkgroupRank(), total);
    if (l == 0u) sums[pc.blocks] = total;
  } else if (pc.phase == kReducePhaseOffsets) {  // counts -> exclusive offsets within each block
    if (g >= pc.blocks) return;
    uint run = sums[g];
    const uint end = min(pc.comps, (g + 1u) * kScanBlock), r = WorkgroupRank();
    for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
      const uint i = c0 + r;
      const uint x = i < end ? counts[i] : 0u;
      const uint at = run + (WorkgroupInclusiveAdd(x, total) - x);
      if (i < end) counts[i] = at;
      run += total;
    }
  } else {  // Concat: one subgroup per component, grid-stride as Local, its lanes copy the segment
    const uint lanes = subgroupBallotBitCount(subgroupBallot(true)), lane = subgroupBallotExclusiveBitCount(subgroupBallot(true));
    const uint slots = SubgroupSlots(), stride = gl_NumWorkGroups.x * gl_NumWorkGroups.y * slots;
    for (uint c = g * slots + gl_SubgroupID; gl_SubgroupID < slots && c < pc.comps; c += stride) {
      const uint next = c + 1u < pc.comps ? counts[c + 1u] : sums[pc.blocks];
      // Fault 1: the last element of every segment is dropped.
      const uint len = next - counts[c] - ((kFault == 1u && next > counts[c]) ? 1u : 0u);
      // Fault 3: each segment is copied from one value late (an off-by-one source index).
      const uint from = c * pc.s + (kFault == 3u ? 1u : 0u);
      for (uint k = lane; k < len; k += lanes) out_values[counts[c] + k] = local_values[from + k];
    }
  }
}
