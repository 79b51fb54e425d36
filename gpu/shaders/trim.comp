#version 460
// Order-preserving compaction as reduce-then-scan over blocks of kScanBlock slots, one workgroup per
// block (mirroring emu ExclusiveScan and PassTrim, whose blocking it shares):
//   kTrimPhaseBlockSums  each workgroup sums its block: strided loads, a workgroup scan in shared memory
//   kTrimPhaseScanSums   one workgroup scans the block sums, kLocalSize at a time with a running carry
//   kTrimPhaseScatter    each workgroup walks its block kLocalSize slots at a time: a workgroup scan of
//                        the flags gives each slot its offset, flagged rays scatter to their dense index
// Reduce-then-scan rather than a single-pass scan with decoupled look-back: look-back needs forward
// progress between workgroups, which lavapipe does not promise.
#include "common.glsl"
#include "workgroup.glsl"

layout(std430, binding = kTrimBindFlags) readonly buffer Flags { uint flags[]; };
layout(std430, binding = kTrimBindSums) buffer Sums { uint sums[]; };  // blocks + 1 (the total last)
layout(std430, binding = kTrimBindOffsets) writeonly buffer Offsets { uint offsets[]; };
layout(std430, binding = kTrimBindSparse) readonly buffer Sparse { Ray sparse[]; };
layout(std430, binding = kTrimBindDense) writeonly buffer Dense { Ray dense[]; };
// carry: flagged slots before this dispatch's part of the stream (a stream larger than one binding
// is trimmed in consecutive parts; offsets are stream-wide, dense indices part-local).
layout(push_constant) uniform Block { TrimPush pc; };

void main() {
  const uint g = WorkGroupIndex(), l = gl_LocalInvocationID.x;
  const uint blocks = (pc.n + kScanBlock - 1u) / kScanBlock;
  uint total;
  if (pc.phase == kTrimPhaseBlockSums) {
    if (g >= blocks) return;  // uniform: the whole workgroup leaves
    WORKGROUP_SUM(flags, g * kScanBlock, min(pc.n, (g + 1u) * kScanBlock), total);
    // Fault kFaultGlobalRace: every invocation stores the (same) block sum, an unordered write-write race.
    if (l == 0u || kFault == kFaultGlobalRace) sums[g] = total;
  } else if (pc.phase == kTrimPhaseScanSums) {
    if (g != 0u) return;
    WORKGROUP_SCAN_IN_PLACE(sums, 0u, blocks, WorkgroupRank(), total);
    if (l == 0u) sums[blocks] = total;
  } else {
    if (g >= blocks) return;
    const uint end = min(pc.n, (g + 1u) * kScanBlock);
    uint run;
    if (kFault != kFaultUndefinedValue || g != 0u) run = sums[kFault == kFaultWorkgroupOffset ? g + 1u : g];
    // Fault kFaultLinearLanes: slots by local index (equal where subgroups are linear and full).
    const uint rank = WorkgroupRank(), r = kFault == kFaultLinearLanes ? l : rank;
    for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
      const uint i = c0 + r;
      // Fault kFaultOutOfBounds: the flag loaded before the bounds check; kFaultFarOutOfBounds: a block on.
      const uint early = kFault == kFaultOutOfBounds ? flags[i] : kFault == kFaultFarOutOfBounds ? flags[i + kScanBlock] : 0u;
      const uint f = i < end ? (kFault == kFaultOutOfBounds ? early : flags[i]) : 0u;
      const uint s = run + (WorkgroupInclusiveAdd(f, total) - f);  // flagged slots before i
      if (i < end) {
        // Fault 1: an inclusive scan where an exclusive one belongs (off by one).
        // Fault 2 (seen only when a stream is trimmed in parts, --split-bytes): the carry is dropped.
        offsets[i] = (kFault == 2u ? 0u : pc.carry) + (kFault == 1u ? s + f : s);
        // Fault 3: the flagged slot's neighbour is gathered (an index off by one).
        if (f != 0u) dense[s] = sparse[kFault == 3u ? i + 1u : i];
      }
      run += total;
    }
  }
}
