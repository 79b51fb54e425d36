#version 460
// Order-preserving compaction in three phases (push constant `phase`), mirroring emu ExclusiveScan
// and PassTrim: 0 block sums, 1 exclusive scan of the block sums (one invocation), 2 block scan and
// scatter. Blocks of kScanBlock slots, as in the emulator.
#include "common.glsl"

layout(std430, binding = kTrimBindFlags) readonly buffer Flags { uint flags[]; };
layout(std430, binding = kTrimBindSums) buffer Sums { uint sums[]; };  // blocks + 1 (the total last)
layout(std430, binding = kTrimBindOffsets) writeonly buffer Offsets { uint offsets[]; };
layout(std430, binding = kTrimBindSparse) readonly buffer Sparse { Ray sparse[]; };
layout(std430, binding = kTrimBindDense) writeonly buffer Dense { Ray dense[]; };
// carry: flagged slots before this dispatch's part of the stream (a stream larger than one binding
// is trimmed in consecutive parts; offsets are stream-wide, dense indices part-local).
layout(push_constant) uniform Block { TrimPush pc; };

void main() {
  const uint b = GlobalIndex();
  const uint blocks = (pc.n + kScanBlock - 1u) / kScanBlock;
  if (pc.phase == kTrimPhaseBlockSums) {
    if (b >= blocks) return;
    uint s = 0u;
    for (uint i = b * kScanBlock; i < min(pc.n, (b + 1u) * kScanBlock); ++i) s += flags[i];
    sums[b] = s;
  } else if (pc.phase == kTrimPhaseScanSums) {
    if (b != 0u) return;
    uint run = 0u;
    for (uint k = 0u; k < blocks; ++k) {
      const uint s = sums[k];
      sums[k] = run;
      run += s;
    }
    sums[blocks] = run;
  } else {
    if (b >= blocks) return;
    uint s = sums[b];
    for (uint i = b * kScanBlock; i < min(pc.n, (b + 1u) * kScanBlock); ++i) {
      // Fault 1: an inclusive scan where an exclusive one belongs (off by one).
      if (kFault == 1u) s += flags[i];
      // Fault 2 (seen only when a stream is trimmed in parts, --split-bytes): the carry is dropped.
      offsets[i] = (kFault == 2u ? 0u : pc.carry) + s;
      if (flags[i] != 0u) dense[s - (kFault == 1u ? 1u : 0u)] = sparse[i];
      if (kFault != 1u) s += flags[i];
    }
  }
}
