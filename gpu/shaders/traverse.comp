#version 460
// Hierarchy traversal of one block: phase Top tests top nodes x triangles (a run of consecutive
// triangles of one top node per invocation), Level tests the children of each surviving pair's
// node, Objects tests top nodes x object spheres (CRSH's culling mask, the
// spheres bound at kTraverseBindTriSpheres); mirrors emu PassTraverseTop / PassTraverseLevel / PassObjectMask.
#include "common.glsl"
#include "cone.glsl"
#include "paged.glsl"

layout(std430, binding = kTraverseBindTriSpheres) readonly buffer TriSpheres { vec4 tri_spheres[]; };
layout(std430, binding = kTraverseBindInfo) readonly buffer Info { TriangleInfo info[]; };
// Phase 0: the object mask's rows for this dispatch's top nodes (t0 ..), objects per row.
layout(std430, binding = kTraverseBindMask) readonly buffer Mask { uint object_mask[]; };
layout(std430, binding = kTraverseBindPairs) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = kTraverseBindFlags) writeonly buffer Flags { uint flags[]; };
layout(std430, binding = kTraverseBindValues) writeonly buffer Values { uint values[]; };
layout(std430, binding = kTraverseBindTested) writeonly buffer Tested { uint tested[]; };
// A level's nodes and the CSR offsets of their children grow with the rays: paged.
PAGED_BUFFER(readonly, Nodes, ConeNode, kTraverseBindNodes)
PAGED_LOAD(Nodes, ConeNode)
PAGED_BUFFER(readonly, First, uint, kTraverseBindFirst)
PAGED_LOAD(First, uint)
layout(push_constant) uniform Block { TraversePush pc; };

ConeNode NodeAt(uint i) { return LoadNodes(i, pc.node_page); }


void main() {
  const uint e = GlobalIndex();
  if (e >= pc.count) return;
  if (pc.phase == kTraversePhaseTop) {
    // Invocation e: run e % runs of row e / runs, kTraverseTopRun slots (rayspace/contract.h).
    const uint runs = (pc.tris + kTraverseTopRun - 1u) / kTraverseTopRun, row = e / runs;
    if (row >= pc.count / pc.tris) return;  // the rows' runs are fewer than the slots
    const uint node = pc.t0 + row, col0 = (e - row * runs) * kTraverseTopRun;
    const ConeNode n = NodeAt(node);
    // Fault 4: each run stops one slot short, leaving its last slot unwritten (its buffers' poison).
    const uint col1 = min(col0 + kTraverseTopRun - (kFault == 4u ? 1u : 0u), pc.tris);
    for (uint col = col0; col < col1; ++col) {
      const uint s = row * pc.tris + col, tri = pc.b0 + col;
      const bool test = pc.use_mask == 0u || object_mask[row * pc.objects + info[tri].ids.y] != 0u;
      tested[s] = test ? 1u : 0u;
      // Fault 1: the top level ignores the triangle sphere's radius (a too-small bound).
      vec4 sphere = tri_spheres[tri];
      if (kFault == 1u) sphere.w = 0.0;
      flags[s] = (test && ConeTestBy(pc.cone_test, n, sphere, pc.eps)) ? 1u : 0u;
      values[s] = ((node - pc.id_base) << kPairTriangleBits) | col;
    }
  } else if (pc.phase == kTraversePhaseObjects) {
    // Fault 2 (seen only when the mask is computed in parts, --split-bytes): the part's start is dropped.
    const uint g = (kFault == 2u ? 0u : pc.t0) + e;  // element of the whole mask; this dispatch writes a part of it
    flags[e] = ConeTestBy(pc.cone_test, NodeAt(g / pc.objects), tri_spheres[g % pc.objects], pc.eps) ? 1u : 0u;
  } else {
    const uint parent = pc.base_up + (pairs[e] >> kPairTriangleBits), tri_local = pairs[e] & kPairTriangleMask;
    const vec4 sphere = tri_spheres[pc.b0 + tri_local];
    const uint c0 = LoadFirst(parent, pc.first_page), c1 = LoadFirst(parent + 1u, pc.first_page);
    tested[e] = c1 - c0;
    for (uint k = 0u; k < pc.children_max; ++k) {
      flags[e * pc.children_max + k] = 0u;
      values[e * pc.children_max + k] = 0u;
    }
    // Fault 3: a level's first child of every parent is skipped (a loop starting one late).
    for (uint c = kFault == 3u ? c0 + 1u : c0; c < c1; ++c) {
      const uint slot = e * pc.children_max + (c - c0);
      flags[slot] = ConeTestBy(pc.cone_test, NodeAt(c), sphere, pc.eps) ? 1u : 0u;
      values[slot] = ((c - pc.base) << kPairTriangleBits) | tri_local;
    }
  }
}
