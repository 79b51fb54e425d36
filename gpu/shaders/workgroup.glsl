// Workgroup building blocks for kernels that cooperate through shared memory. Include after
// common.glsl. Every function with a barrier must be called by all invocations of the workgroup, in
// uniform control flow.
#ifndef RAYSPACE_WORKGROUP_GLSL
#define RAYSPACE_WORKGROUP_GLSL

// The most invocations a workgroup may have (kLocalSize <= this; the host's --local-size range).
const uint kMaxLocalSize = 1024u;
shared uint wg_tile[kMaxLocalSize];

// This workgroup's index in the launch, rows of groups read in order (vk::Recorder::Dispatch folds
// launches wider than maxComputeWorkGroupCount[0]); uniform across the workgroup.
uint WorkGroupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// Inclusive prefix sum of `v` over the workgroup's invocations in local-id order (Hillis-Steele in
// shared memory: log2(kLocalSize) steps, each read, barrier, add, barrier); `total` receives the sum
// of all. Integer sums, so the result does not depend on the order the device runs invocations in.
uint WorkgroupInclusiveAdd(uint v, out uint total) {
  const uint l = gl_LocalInvocationID.x;
  wg_tile[l] = v;
  barrier();
  for (uint d = 1u; d < kLocalSize; d <<= 1u) {
    const uint t = l >= d ? wg_tile[l - d] : 0u;
    barrier();
    wg_tile[l] += t;
    barrier();
  }
  const uint r = wg_tile[l];
  total = wg_tile[kLocalSize - 1u];
  barrier();  // the tile is free for the next call
  return r;
}

#endif
