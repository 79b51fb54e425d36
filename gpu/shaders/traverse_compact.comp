#version 460
// The traversal fused with its stream reduction (mirrors emu PassTraverseTopCompacted /
// PassTraverseLevelCompacted): the survivors of traverse.comp's slots, in slot order, without the
// flag and value arrays and the separate reduce pass. Three dispatches (four at the top: Groups first; rayspace/contract.h), over
// blocks: a block is a top node's row of slots at the top level, kCompactBlock slots below.
//   kTraverseCompactPhaseGroups one workgroup per round of the top phase: each subgroup's group sphere
//       of its triangles, which the top phase's subgroups cull rows by (cone_cull.glsl), and each
//       invocation's object word (the one object of its triangles, or kCompactMixedObjects)
//   kTraverseCompactPhaseTop    one workgroup per tile of kCompactRows rows: every invocation holds
//       kCompactCols consecutive triangles of a round and tests them against each row's node, which
//       the subgroup's lanes load once and pass around by shuffle (a node per test from memory costs
//       a CPU device more than the test); one workgroup scan of the rows' packed counts places each
//       round's survivors after the rounds before, in the row's region of the scratch buffer
//   kTraverseCompactPhaseLevel  one workgroup per block, in rounds of kLocalSize (pair, chunk)s: each
//       invocation tests a pair's chunk of children (shared in the subgroup when the pairs share a
//       parent), one workgroup scan places them
//   kTraverseCompactPhaseScan   one workgroup: exclusive scan of the block counts, sum of the tests
//   kTraverseCompactPhaseScatter one workgroup per block copies its survivors to its offset
// Reduce-then-scan, no decoupled look-back: look-back needs forward progress between workgroups,
// which lavapipe does not promise.
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_KHR_shader_subgroup_vote : require
#include "common.glsl"
#include "cone.glsl"
#include "cone_cull.glsl"
#include "paged.glsl"
#include "workgroup.glsl"

layout(std430, binding = kTraverseCompactBindTriSpheres) readonly buffer TriSpheres { vec4 tri_spheres[]; };
layout(std430, binding = kTraverseCompactBindInfo) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = kTraverseCompactBindMask) readonly buffer Mask { uint object_mask[]; };  // per tile and object
layout(std430, binding = kTraverseCompactBindPairs) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = kTraverseCompactBindScratch) buffer Scratch { uint scratch[]; };
layout(std430, binding = kTraverseCompactBindCounts) buffer Counts { uint counts[]; };  // blocks + 1
layout(std430, binding = kTraverseCompactBindTested) buffer Tested { uint tested[]; };  // blocks + 1
layout(std430, binding = kTraverseCompactBindOut) writeonly buffer Out { uint out_pairs[]; };
// Per round, kCompactGroupWords words an invocation: a group sphere per subgroup (4 words each, room
// for kLocalSize subgroups), then an object word per invocation.
layout(std430, binding = kTraverseCompactBindGroups) buffer Groups { uint group_words[]; };
PAGED_BUFFER(readonly, Nodes, ConeNode, kTraverseCompactBindNodes)
PAGED_LOAD(Nodes, ConeNode)
PAGED_BUFFER(readonly, First, uint, kTraverseCompactBindFirst)
PAGED_LOAD(First, uint)
layout(push_constant) uniform Block { TraverseCompactPush pc; };

// kTraverseCompactPhaseTop's counts, kCompactRows per invocation and round, two 16-bit fields a
// word (a round has at most kMaxLocalSize x kCompactCols < 2^16 survivors per row), scanned at once.
// One per subgroup: the host keeps subgroups <= kMaxLocalSize / 4, and there are never more than invocations.
shared uvec4 wg_tile4[kLocalSize < kMaxLocalSize / 4u ? kLocalSize : kMaxLocalSize / 4u];
uvec4 WorkgroupInclusiveAdd4(uvec4 v, out uvec4 total) {
  const uvec4 inclusive = subgroupInclusiveAdd(v);
  const uvec4 subgroup_sum = subgroupAdd(v);
  if (subgroupElect()) wg_tile4[gl_SubgroupID] = subgroup_sum;
  barrier();
  uvec4 before = uvec4(0u), all = uvec4(0u);
  for (uint k = 0u; k < NumSubgroups(); ++k) {
    const uvec4 x = wg_tile4[k];
    if (k < gl_SubgroupID) before += x;
    all += x;
  }
  total = all;
  barrier();  // the tile is free for the next round
  return before + inclusive;
}
uint Field(uvec4 v, uint r) { return (v[r >> 1u] >> ((r & 1u) * 16u)) & 0xFFFFu; }

// Bit r: may row0 + r's node meet triangles of `object` (the object mask; all rows without one)?
// The host packs the mask a word per tile and object (bit r: the tile's row r), so one load answers
// for the tile's rows (lavapipe loads lane by lane).
uint RowBits(uint object, uint row0, uint rows) {
  if (pc.use_mask == 0u) return (1u << rows) - 1u;
  return object_mask[(row0 / kCompactRows) * pc.objects + object];
}

// Lane `lane`'s node, to every lane of the subgroup (both phases pass nodes around this way).
ConeNode ShuffleNode(ConeNode mine, uint lane) {
  ConeNode n;
  n.sphere = subgroupShuffle(mine.sphere, lane);
  n.cone = subgroupShuffle(mine.cone, lane);
  n.extra = subgroupShuffle(mine.extra, lane);
  return n;
}

// Row r's node: lane r of the subgroup loaded it, when lanes 0 .. kCompactRows - 1 are all there (a
// subgroup is not promised full: the last one of a workgroup whose size is not a multiple of
// gl_SubgroupSize is not, e.g. at local size 7); else memory. `shared_rows`: SharedRows(), uniform.
bool SharedRows() {
  return gl_SubgroupSize >= kCompactRows && (subgroupBallot(true).x & ((1u << kCompactRows) - 1u)) == (1u << kCompactRows) - 1u;
}
ConeNode RowNode(ConeNode mine, uint row0, uint r, bool shared_rows) {
  if (!shared_rows) return LoadNodes(pc.t0 + row0 + r, pc.node_page);
  return ShuffleNode(mine, r);
}

uint GroupWords() { return kLocalSize * kCompactGroupWords; }
uint SphereWord(uint round) { return round * GroupWords() + gl_SubgroupID * 4u; }
uint ObjectWord(uint round, uint rank) { return round * GroupWords() + kLocalSize * 4u + rank; }
// Whether this subgroup holds the ranks (WorkgroupRank) k * gl_SubgroupSize onwards, as many as a
// linear layout gives subgroup k: then its triangles are those of group k in every dispatch, which a
// device need not lay out alike. Uniform in the subgroup; always so on a linear, full layout.
bool Aligned(uint rank) {
  const uint first = gl_SubgroupID * gl_SubgroupSize;
  return first < kLocalSize && subgroupMin(rank) == first &&
         subgroupBallotBitCount(subgroupBallot(true)) == min(gl_SubgroupSize, kLocalSize - first);
}
vec4 GroupSphere(uint round) {
  const uint w = SphereWord(round);
  return uintBitsToFloat(uvec4(group_words[w], group_words[w + 1u], group_words[w + 2u], group_words[w + 3u]));
}

// Phase Groups for round `round` of the top phase (its columns, lanes and subgroups): each subgroup
// bounds its lanes' triangles, kCompactCols each, by subgroup min/max: the box of the centres, the
// box's centre, the largest reach from it (cone_cull.glsl). A negative radius marks a group the
// bound may not judge. Each invocation also writes the object its triangles share, or
// kCompactMixedObjects: the top phase then loads one word a round, not an object id per triangle
// (lavapipe loads lane by lane). Computed once per call rather than once per tile of rows.
void GroupsOfRound(uint round) {
  const uint rank = WorkgroupRank(), col0 = round * kLocalSize * kCompactCols + rank * kCompactCols;
  vec4 sphere[kCompactCols];
  vec3 lo = vec3(kDeviceCullLimit), hi = vec3(-kDeviceCullLimit);
  bool ok = true;
  uint object = kCompactMixedObjects;
  for (uint i = 0u; i < kCompactCols; ++i) {
    if (col0 + i >= pc.tris) continue;
    // Fault 7: the first triangle's object taken for all of the invocation's triangles. Without a
    // mask the top phase reads no object (uniform).
    const uint o = pc.use_mask == 0u ? 0u : info[pc.b0 + col0 + i].ids.y;
    if (i == 0u)
      object = o;
    else if (o != object && kFault != 7u)
      object = kCompactMixedObjects;  // no object id is kCompactMixedObjects (the host checks)
    sphere[i] = tri_spheres[pc.b0 + col0 + i];
    ok = ok && DeviceCullable(sphere[i]);
    lo = min(lo, sphere[i].xyz);
    hi = max(hi, sphere[i].xyz);
  }
  lo = subgroupMin(lo);
  hi = subgroupMax(hi);
  ok = subgroupMin(ok ? 1u : 0u) != 0u;
  precise const vec3 c = (lo + hi) * 0.5;
  float reach = 0.0;
  for (uint i = 0u; i < kCompactCols; ++i)
    if (col0 + i < pc.tris) reach = max(reach, DeviceReach(sphere[i], c));
  precise const float radius = subgroupMax(reach) * kDeviceCullRadiusUp;
  group_words[ObjectWord(round, rank)] = object;
  const bool judged = ok && Aligned(rank);
  if (subgroupElect()) {
    const uvec4 v = floatBitsToUint(vec4(c, judged ? radius : -1.0));
    const uint w = SphereWord(round);
    group_words[w] = v.x, group_words[w + 1u] = v.y, group_words[w + 2u] = v.z, group_words[w + 3u] = v.w;
  }
}

// The rows of the tile that may keep any of the subgroup's triangles this round: all of them, less
// those whose node provably misses the subgroup's group (Groups): lane r tests row r's node (`mine`),
// one test per row for the subgroup's gl_SubgroupSize x kCompactCols slots, and a ballot gathers
// them. Uniform in the subgroup. Only the conservative cone test culls, and only where the rows'
// nodes are shared (SharedRows).
uint LiveRows(ConeNode mine, uint round, uint rows, bool shared_rows, bool aligned) {
  const uint all_rows = (1u << rows) - 1u;
  if (!shared_rows || !aligned || pc.cone_test != kConeTestConservative) return all_rows;
  const vec4 group = GroupSphere(round);
  const bool miss = gl_SubgroupInvocationID < rows && DeviceGroupMisses(mine, group, pc.eps);
  return all_rows & ~subgroupBallot(miss).x;
}

// Phase A at the top level for the tile of rows [row0, row0 + rows) of this dispatch's part: slot
// (row, col) is top node t0 + row against triangle b0 + col, with traverse.comp's packing and
// object-mask rule; row r's survivors go to its slots' region, scratch[(row0 + r) * tris ..].
void TestTopTile(uint g) {
  const uint row0 = g * kCompactRows, rows = min(kCompactRows, pc.count / pc.tris - row0), l = gl_LocalInvocationID.x;
  const ConeNode mine = LoadNodes(pc.t0 + row0 + min(gl_SubgroupInvocationID, rows - 1u), pc.node_page);
  const bool shared_rows = SharedRows();
  const uint rank = WorkgroupRank();
  const bool aligned = Aligned(rank);
  uint run[kCompactRows];  // survivors of the rounds before, per row
  for (uint r = 0u; r < kCompactRows; ++r) run[r] = 0u;
  uint tests = 0u;
  // The last object's row bits, kept across rounds: an invocation's triangles mostly share an object,
  // and its rounds mostly keep it.
  uint object = kCompactMixedObjects, object_bits = 0u;
  for (uint c0 = 0u; c0 < pc.tris; c0 += kLocalSize * kCompactCols) {
    const uint col0 = c0 + rank * kCompactCols;
    vec4 sphere[kCompactCols];
    uint may[kCompactCols];  // bit r: row r tests this triangle
    const uint round = c0 / (kLocalSize * kCompactCols);
    // Without a mask every row tests every triangle: no object is needed.
    const uint shared_object = pc.use_mask == 0u ? 0u : group_words[ObjectWord(round, rank)];
    for (uint i = 0u; i < kCompactCols; ++i) {
      may[i] = 0u;
      if (col0 + i >= pc.tris) continue;
      const uint o = shared_object != kCompactMixedObjects ? shared_object : info[pc.b0 + col0 + i].ids.y;
      if (o != object) object_bits = RowBits(o, row0, rows);
      object = o;
      may[i] = object_bits;
    }
    for (uint i = 0u; i < kCompactCols; ++i) tests += bitCount(may[i]);  // culled or not, every slot counts
    const uint live = LiveRows(mine, round, rows, shared_rows, aligned);
    // The spheres only for a subgroup with a live row (uniform in the subgroup): lavapipe loads lane
    // by lane, and a culled subgroup would load them for nothing.
    if (live != 0u)
      for (uint i = 0u; i < kCompactCols; ++i)
        if (col0 + i < pc.tris) sphere[i] = tri_spheres[pc.b0 + col0 + i];
    uint hit[kCompactRows];  // bit i: column col0 + i survives in row r
    for (uint r = 0u; r < kCompactRows; ++r) hit[r] = 0u;
    // A loop over the live rows, not a branch per row: the set is the same on every lane of the
    // subgroup, so a culled row costs nothing (a SIMD device runs a masked-off branch all the same).
    for (uint bits = live; bits != 0u; bits &= bits - 1u) {
      const uint r = findLSB(bits);
      const ConeNode node = RowNode(mine, row0, r, shared_rows);
      for (uint i = 0u; i < kCompactCols; ++i)
        if ((may[i] >> r & 1u) != 0u && ConeTestBy(pc.cone_test, node, sphere[i], pc.eps)) hit[r] |= 1u << i;
    }
    uvec4 n = uvec4(0u);
    for (uint r = 0u; r < rows; ++r) n[r >> 1u] += bitCount(hit[r]) << ((r & 1u) * 16u);
    uvec4 sums;
    const uvec4 before = WorkgroupInclusiveAdd4(n, sums) - n;  // fieldwise: no field borrows
    for (uint r = 0u; r < rows; ++r) {
      // Fault 3: every round starts at the row's start (the carry between rounds is dropped).
      uint at = (row0 + r) * pc.tris + (kFault == 3u ? 0u : run[r]) + Field(before, r);
      for (uint bits = hit[r]; bits != 0u; bits &= bits - 1u)
        scratch[at++] = ((pc.t0 + row0 + r - pc.id_base) << kPairTriangleBits) | (col0 + uint(findLSB(bits)));
      run[r] += Field(sums, r);
    }
  }
  uint all_tests;
  WorkgroupInclusiveAdd(tests, all_tests);
  if (l == 0u) {
    for (uint r = 0u; r < rows; ++r) {
      // Fault 2: the last survivor of every block is dropped. Fault 4: the survivors reported as tests.
      counts[row0 + r] = (kFault == 2u && run[r] > 0u) ? run[r] - 1u : run[r];
      tested[row0 + r] = kFault == 4u ? run[r] : (r == 0u ? all_tests : 0u);
    }
  }
}

// Phase A one level down for block g, slots [first, end) (slot (p, k) is child k of the node of pair
// p, p * children_max + k as in traverse.comp). A pair's children come in chunks of kCompactChunk, a
// word of bits each (one chunk unless children_max > kCompactChunk); the block's (pair, chunk)s in
// slot order are walked in rounds of kLocalSize, one per invocation, one workgroup scan of
// (survivors, tests) a round. Only slots that hold a child are tested. When a subgroup's pairs share
// their parent (consecutive pairs mostly do: the level above keeps a node's triangles together),
// lane j loads child j once and the subgroup's lanes pass the nodes around by shuffle: lavapipe
// runs every buffer load lane by lane, so a node loaded per test cost more than the test. Uniform
// control flow: every invocation runs every round.
void TestBlock(uint g) {
  const uint cm = pc.children_max, chunks = (cm + kCompactChunk - 1u) / kCompactChunk;
  const uint first = g * kCompactBlock, end = min(pc.count, first + kCompactBlock), l = gl_LocalInvocationID.x;
  const bool full = subgroupBallotBitCount(subgroupBallot(true)) == gl_SubgroupSize;  // every lane there to shuffle from
  const uint rank = WorkgroupRank();
  uint run = 0u, tests = 0u;  // survivors and tests of the rounds before
  for (uint v0 = first / cm * chunks; v0 / chunks * cm < end; v0 += kLocalSize) {
    const uint v = v0 + rank, p = v / chunks, kc = (v - p * chunks) * kCompactChunk;
    const bool valid = p * cm < end;
    uint parent = 0xFFFFFFFFu, tri_local = 0u, c0 = 0u, children = 0u, a = 0u, b = 0u;
    vec4 sphere = vec4(0.0);
    if (valid) {
      const uint pair = pairs[p];
      parent = pc.base_up + (pair >> kPairTriangleBits);
      tri_local = pair & kPairTriangleMask;
      sphere = tri_spheres[pc.b0 + tri_local];
      c0 = LoadFirst(parent, pc.first_page);
      children = LoadFirst(parent + 1u, pc.first_page) - c0;
      // The chunk's children that the block holds (a block may begin or end inside a pair) and exist.
      a = max(max(first, p * cm) - p * cm, kc);
      b = max(a, min(min(end - p * cm, children), kc + kCompactChunk));
    }
    // Fault 6: pairs whose parents have as many children are taken to share them. The subgroup
    // operations run on every lane, before the comparison that differs between lanes.
    const uint lead = kFault == 6u ? subgroupMax(children) : subgroupMin(parent);
    const bool shared_nodes = full && subgroupAll(!valid || (kFault == 6u ? children : parent) == lead);
    uint hit = 0u;  // bit i: child kc + i survives
    if (shared_nodes) {
      // The children the subgroup's non-empty chunks test, and no more (an empty chunk's a may lie
      // past its parent's children).
      const uint sc0 = subgroupMax(c0), sa = subgroupMin(a < b ? a : 0xFFFFFFFFu), sb = subgroupMax(a < b ? b : 0u);
      for (uint k0 = sa; k0 < sb; k0 += gl_SubgroupSize) {
        ConeNode mine;
        if (k0 + gl_SubgroupInvocationID < sb) mine = LoadNodes(sc0 + k0 + gl_SubgroupInvocationID, pc.node_page);
        for (uint j = 0u; j < gl_SubgroupSize && k0 + j < sb; ++j) {
          const ConeNode node = ShuffleNode(mine, j);
          const uint k = k0 + j;
          if (k >= a && k < b && ConeTestBy(pc.cone_test, node, sphere, pc.eps)) hit |= 1u << (k - kc);
        }
      }
    } else {
      for (uint k = a; k < b; ++k)
        if (ConeTestBy(pc.cone_test, LoadNodes(c0 + k, pc.node_page), sphere, pc.eps)) hit |= 1u << (k - kc);
    }
    const uint n = bitCount(hit);
    // One scan for both counts, 16 bits each: a round has at most kMaxLocalSize x kCompactChunk < 2^16.
    uint sums;
    const uint before = (WorkgroupInclusiveAdd(n | ((b - a) << 16), sums) & 0xFFFFu) - n;
    // Fault 3: every round starts at the block's start (the carry between rounds is dropped).
    uint at = first + (kFault == 3u ? 0u : run) + before;
    for (uint bits = hit; bits != 0u; bits &= bits - 1u)
      scratch[at++] = ((c0 + kc + uint(findLSB(bits)) - pc.base) << kPairTriangleBits) | tri_local;
    run += sums & 0xFFFFu;
    tests += sums >> 16;
  }
  if (l == 0u) {
    // Fault 2: the last survivor of every block is dropped. Fault 4: the survivors reported as tests.
    counts[g] = (kFault == 2u && run > 0u) ? run - 1u : run;
    tested[g] = kFault == 4u ? run : tests;
  }
}

// Phase C for block g: its survivors from its scratch region (pc.region slots a block) to its offset.
void ScatterBlock(uint g) {
  const uint at = counts[g], n = counts[g + 1u] - at;
  // Fault 1: the block lands at the next block's offset (the scan read as inclusive).
  const uint dst = kFault == 1u ? counts[g + 1u] : at;
  for (uint k = gl_LocalInvocationID.x; k < n; k += kLocalSize)
    if (dst + k < pc.count) out_pairs[dst + k] = scratch[g * pc.region + k];  // the bound holds but for fault 1
}

void main() {
  const uint g = WorkGroupIndex();
  if (pc.phase == kTraverseCompactPhaseScan) {
    if (g != 0u) return;
    uint total;
    WORKGROUP_SCAN_IN_PLACE(counts, 0u, pc.blocks, WorkgroupRank(), total);
    if (gl_LocalInvocationID.x == 0u) counts[pc.blocks] = total;
    WORKGROUP_SUM(tested, 0u, pc.blocks, total);
    if (gl_LocalInvocationID.x == 0u) tested[pc.blocks] = total;
  } else if (pc.phase == kTraverseCompactPhaseGroups) {
    if (g < (pc.tris + kLocalSize * kCompactCols - 1u) / (kLocalSize * kCompactCols)) GroupsOfRound(g);  // uniform
  } else if (g < pc.blocks) {  // uniform: the whole workgroup leaves
    // Level and Scatter: a grid of at most kCompactStrideGroups strides over the blocks (uniform).
    const uint grid = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    if (pc.phase == kTraverseCompactPhaseScatter)
      for (uint b = g; b < pc.blocks; b += grid) ScatterBlock(b);
    else if (pc.phase == kTraverseCompactPhaseLevel)
      for (uint b = g; b < pc.blocks; b += grid) TestBlock(b);
    else if (g * kCompactRows < pc.blocks)
      TestTopTile(g);
  }
}
