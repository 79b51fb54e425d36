// Workgroup building blocks for kernels that cooperate through shared memory. Include after
// common.glsl. Every function with a barrier must be called by all invocations of the workgroup, in
// uniform control flow.
#ifndef RAYSPACE_WORKGROUP_GLSL
#define RAYSPACE_WORKGROUP_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require

shared uint wg_tile[kLocalSize];  // one word per subgroup: never more subgroups than invocations

// This workgroup's index in the launch, rows of groups read in order (vk::Recorder::Dispatch folds
// launches wider than maxComputeWorkGroupCount[0]); uniform across the workgroup.
uint WorkGroupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// The subgroups of a workgroup: gl_NumSubgroups, but never fewer than ceil(kLocalSize /
// gl_SubgroupSize), since a subgroup holds at most gl_SubgroupSize invocations. With workgroups of 12
// or 20 invocations and subgroups of 8, lavapipe's gl_NumSubgroups is floor(kLocalSize /
// gl_SubgroupSize), one short (cli.diff.cornell.crsh.local-size-12 and -20 diverge with it alone).
uint NumSubgroups() { return max(gl_NumSubgroups, (kLocalSize + gl_SubgroupSize - 1u) / gl_SubgroupSize); }
// The subgroups a workgroup has at the least, the same in every workgroup: kernels with a subgroup
// per item give each workgroup this many items (the host sizes their grids by it).
uint SubgroupSlots() { return (kLocalSize + gl_SubgroupSize - 1u) / gl_SubgroupSize; }

// This invocation's rank in the workgroup, 0 .. kLocalSize - 1: subgroups in gl_SubgroupID order, then
// a subgroup's active lanes in lane order, the order the scans below add in. Vulkan ties no lane to a
// local index, and unless a pipeline requires full subgroups one may launch with lanes idle, so a
// kernel that scans slots in order hands slot c0 + rank to each invocation, never c0 + its local index.
// On a device that lays subgroups out linearly and full (lavapipe) the rank is the local index. Two
// barriers; call in uniform control flow. The counts fill the tile from its top, the scans' sums
// from its bottom: a scan that reads a word no subgroup published (a planted shared-off-by-one)
// then reads a word never written, which a checker reports, not a stale count.
uint WorkgroupRank() {
  const uvec4 here = subgroupBallot(true);
  if (subgroupElect()) wg_tile[kLocalSize - 1u - gl_SubgroupID] = subgroupBallotBitCount(here);
  barrier();
  uint before = 0u;
  for (uint k = 0u; k < gl_SubgroupID; ++k) before += wg_tile[kLocalSize - 1u - k];
  barrier();  // the tile is free for the scans
  return before + subgroupBallotExclusiveBitCount(here);
}

// Inclusive prefix sum of `v` over the workgroup's invocations in rank order (WorkgroupRank);
// `total` receives the sum of all. Subgroups scan their own active lanes (subgroupInclusiveAdd), one
// lane of each publishes its subgroup's sum in shared memory, and after one barrier every invocation adds the sums of the subgroups before
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
// carry (no invocation loops over the whole range alone); RANK is WorkgroupRank(), TOTAL receives the
// sum.
#define WORKGROUP_SCAN_IN_PLACE(BUF, FIRST, COUNT, RANK, TOTAL)                            \
  {                                                                                        \
    uint wg_carry_ = 0u, wg_chunk_;                                                        \
    for (uint wg_c0_ = 0u; wg_c0_ < (COUNT); wg_c0_ += kLocalSize) {                       \
      const uint wg_k_ = wg_c0_ + (RANK);                                                  \
      const uint wg_v_ = wg_k_ < (COUNT) ? BUF[(FIRST) + wg_k_] : 0u;                      \
      const uint wg_inc_ = WorkgroupInclusiveAdd(wg_v_, wg_chunk_);                        \
      if (wg_k_ < (COUNT)) BUF[(FIRST) + wg_k_] = wg_carry_ + (wg_inc_ - wg_v_);           \
      wg_carry_ += wg_chunk_;                                                              \
    }                                                                                      \
    TOTAL = wg_carry_;                                                                     \
  }

#endif
