// Workgroup building blocks for kernels that cooperate through shared memory. Include after
// common.glsl. Every function with a barrier must be called by all invocations of the workgroup, in
// uniform control flow.
#ifndef RAYSPACE_WORKGROUP_GLSL
#define RAYSPACE_WORKGROUP_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require

shared uint wg_tile[kMaxLocalSize];  // one word per subgroup (rayspace/contract.h)

// This workgroup's index in the launch, rows of groups read in order (vk::Recorder::Dispatch folds
// launches wider than maxComputeWorkGroupCount[0]); uniform across the workgroup.
uint WorkGroupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// The subgroups of a workgroup, the last one partial when kLocalSize is not a multiple of the
// subgroup size. Not gl_NumSubgroups: with workgroups of 12 or 20 invocations and subgroups of 8,
// lavapipe's scans behave as if it were floor(kLocalSize / gl_SubgroupSize) and drop the partial
// subgroup's sum (cli.diff.cornell.crsh.local-size-12 and -20 diverge with it and pass without).
uint NumSubgroups() { return (kLocalSize + gl_SubgroupSize - 1u) / gl_SubgroupSize; }

// Inclusive prefix sum of `v` over the workgroup's invocations in local-id order; `total` receives
// the sum of all. Subgroups scan their own lanes (subgroupInclusiveAdd; lanes are local ids in order,
// gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID), one lane of each publishes its subgroup's
// sum in shared memory, and after one barrier every invocation adds the sums of the subgroups before
// its own: two barriers a call, whatever the workgroup size (the device's subgroup size is read, not
// assumed). Integer sums, so the result does not depend on the order the device runs invocations in.
// The planted faults kFault* of rayspace/contract.h live here, as in the emulator's mirror
// (emu/src/workgroup_ops.cpp).
uint WorkgroupInclusiveAdd(uint v, out uint total) {
  const uint inclusive = subgroupInclusiveAdd(v);
  const uint subgroup_sum = subgroupAdd(v);
  const bool wide = kFault == kFaultSubgroup32;
  const uint subgroup = wide ? gl_LocalInvocationID.x / 32u : gl_SubgroupID;
  const uint subgroups = wide ? (kLocalSize + 31u) / 32u : NumSubgroups();
  if (subgroupElect()) wg_tile[subgroup + (kFault == kFaultSharedOffByOne ? 1u : 0u)] = subgroup_sum;
  if (kFault == kFaultDivergentBarrier) {
    if (gl_LocalInvocationID.x < kLocalSize / 2u) barrier();
  } else if (kFault != kFaultDroppedBarrier) {
    barrier();
  }
  uint before = 0u, all = 0u;
  for (uint k = 0u; k < subgroups; ++k) {
    const uint x = wg_tile[k];
    before += k < subgroup ? x : 0u;
    all += x;
  }
  total = all;
  barrier();  // the tile is free for the next call
  return before + inclusive;
}

// Buffer-generic helpers as macros (GLSL has no buffer references here). Every invocation of the
// workgroup runs them and receives the same `total`.
// The sum of BUF[I0 .. I1): strided loads, then a workgroup scan.
#define WORKGROUP_SUM(BUF, I0, I1, TOTAL)                                                  \
  {                                                                                        \
    uint wg_s_ = 0u;                                                                       \
    for (uint wg_i_ = (I0) + gl_LocalInvocationID.x; wg_i_ < (I1); wg_i_ += kLocalSize)    \
      wg_s_ += BUF[wg_i_];                                                                 \
    WorkgroupInclusiveAdd(wg_s_, TOTAL);                                                   \
  }
// Exclusive scan of BUF[FIRST .. FIRST + COUNT) in place, kLocalSize words at a time with a running
// carry (no invocation loops over the whole range alone); TOTAL receives the sum.
#define WORKGROUP_SCAN_IN_PLACE(BUF, FIRST, COUNT, TOTAL)                                  \
  {                                                                                        \
    uint wg_carry_ = 0u, wg_chunk_;                                                        \
    for (uint wg_c0_ = 0u; wg_c0_ < (COUNT); wg_c0_ += kLocalSize) {                       \
      const uint wg_k_ = wg_c0_ + gl_LocalInvocationID.x;                                  \
      const uint wg_v_ = wg_k_ < (COUNT) ? BUF[(FIRST) + wg_k_] : 0u;                      \
      const uint wg_inc_ = WorkgroupInclusiveAdd(wg_v_, wg_chunk_);                        \
      if (wg_k_ < (COUNT)) BUF[(FIRST) + wg_k_] = wg_carry_ + (wg_inc_ - wg_v_);           \
      wg_carry_ += wg_chunk_;                                                              \
    }                                                                                      \
    TOTAL = wg_carry_;                                                                     \
  }

#endif
