#version 460
// Stream reduction of (flag, value) slots to the flagged values in slot order; mirrors emu
// ReduceHierarchical (Roger et al.: components of s slots reduced on their own, then concatenated)
// and ReduceScan (phases FlagSums, ScanSums, Scatter: block sums of the flags, scan of the sums,
// block scan and scatter, as emu ExclusiveScan). Scans are blocked so no loop passes 65,535 iterations.
#include "common.glsl"

layout(std430, binding = kReduceBindFlags) readonly buffer Flags { uint flags[]; };
layout(std430, binding = kReduceBindValues) readonly buffer Values { uint values[]; };
layout(std430, binding = kReduceBindLocal) buffer Local { uint local_values[]; };
layout(std430, binding = kReduceBindCounts) buffer Counts { uint counts[]; };   // per component, then exclusive offsets
layout(std430, binding = kReduceBindSums) buffer Sums { uint sums[]; };       // per block of kScanBlock counts, plus total
layout(std430, binding = kReduceBindOut) writeonly buffer Out { uint out_values[]; };
layout(push_constant) uniform Block { ReducePush pc; };

void main() {
  const uint t = GlobalIndex();
  if (pc.phase == kReducePhaseFlagSums) {  // scan-based: block sums of the flags
    if (t >= pc.blocks) return;
    uint sum = 0u;
    for (uint i = t * kScanBlock; i < min(pc.n, (t + 1u) * kScanBlock); ++i) sum += flags[i];
    sums[t] = sum;
    return;
  }
  if (pc.phase == kReducePhaseScatter) {  // scan-based: block scan and scatter (after ScanSums scanned the sums)
    if (t >= pc.blocks) return;
    // Fault 2: each block starts at the previous block's offset (an off-by-one in the scan).
    uint run = (kFault == 2u && t > 0u) ? sums[t - 1u] : sums[t];
    for (uint i = t * kScanBlock; i < min(pc.n, (t + 1u) * kScanBlock); ++i) {
      if (flags[i] != 0u) {
        out_values[run] = values[i];
        ++run;
      }
    }
    return;
  }
  if (pc.phase == kReducePhaseLocal) {  // reduce each component locally
    if (t >= pc.comps) return;
    uint k = 0u;
    for (uint i = t * pc.s; i < min(pc.n, (t + 1u) * pc.s); ++i) {
      if (flags[i] != 0u) {
        local_values[t * pc.s + k] = values[i];
        ++k;
      }
    }
    counts[t] = k;
  } else if (pc.phase == kReducePhaseBlockSums) {  // block sums of the counts
    if (t >= pc.blocks) return;
    uint sum = 0u;
    for (uint i = t * kScanBlock; i < min(pc.comps, (t + 1u) * kScanBlock); ++i) sum += counts[i];
    sums[t] = sum;
  } else if (pc.phase == kReducePhaseScanSums) {  // scan of the block sums
    if (t != 0u) return;
    uint run = 0u;
    for (uint b = 0u; b < pc.blocks; ++b) {
      const uint x = sums[b];
      sums[b] = run;
      run += x;
    }
    sums[pc.blocks] = run;
  } else if (pc.phase == kReducePhaseOffsets) {  // counts -> exclusive offsets within each block
    if (t >= pc.blocks) return;
    uint run = sums[t];
    for (uint i = t * kScanBlock; i < min(pc.comps, (t + 1u) * kScanBlock); ++i) {
      const uint x = counts[i];
      counts[i] = run;
      run += x;
    }
  } else {  // concatenate: component t's segment goes to its offset
    if (t >= pc.comps) return;
    const uint next = t + 1u < pc.comps ? counts[t + 1u] : sums[pc.blocks];
    // Fault 1: the last element of every segment is dropped.
    const uint len = next - counts[t] - ((kFault == 1u && next > counts[t]) ? 1u : 0u);
    for (uint k = 0u; k < len; ++k) out_values[counts[t] + k] = local_values[t * pc.s + k];
  }
}
