#version 460
// Order-preserving compaction in three phases (push constant `phase`), mirroring emu ExclusiveScan
// and PassTrim: 0 block sums, 1 exclusive scan of the block sums (one invocation), 2 block scan and
// scatter. Blocks of 4096 slots, as in the emulator.
#include "common.glsl"

layout(std430, binding = 0) readonly buffer Flags { uint flags[]; };
layout(std430, binding = 1) buffer Sums { uint sums[]; };  // blocks + 1 (the total last)
layout(std430, binding = 2) writeonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 3) readonly buffer Sparse { Ray sparse[]; };
layout(std430, binding = 4) writeonly buffer Dense { Ray dense[]; };
layout(push_constant) uniform Push { uint n; uint phase; } pc;

const uint kBlock = 4096u;

void main() {
  const uint b = gl_GlobalInvocationID.x;
  const uint blocks = (pc.n + kBlock - 1u) / kBlock;
  if (pc.phase == 0u) {
    if (b >= blocks) return;
    uint s = 0u;
    for (uint i = b * kBlock; i < min(pc.n, (b + 1u) * kBlock); ++i) s += flags[i];
    sums[b] = s;
  } else if (pc.phase == 1u) {
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
    for (uint i = b * kBlock; i < min(pc.n, (b + 1u) * kBlock); ++i) {
      // Fault 1: an inclusive scan where an exclusive one belongs (off by one).
      if (kFault == 1u) s += flags[i];
      offsets[i] = s;
      if (flags[i] != 0u) dense[s - (kFault == 1u ? 1u : 0u)] = sparse[i];
      if (kFault != 1u) s += flags[i];
    }
  }
}
