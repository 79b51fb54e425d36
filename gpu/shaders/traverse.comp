#version 460
// Hierarchy traversal of one block: phase 0 tests top nodes x triangles, phase 1 tests the children
// of each surviving pair's node, phase 2 tests top nodes x object spheres (CRSH's culling mask, the
// spheres bound as binding 1); mirrors emu PassTraverseTop / PassTraverseLevel / PassObjectMask.
#include "common.glsl"
#include "cone.glsl"
#include "paged.glsl"

layout(std430, binding = 0) readonly buffer TriSpheres { vec4 tri_spheres[]; };
layout(std430, binding = 1) readonly buffer Info { TriangleInfo info[]; };
// Phase 0: the object mask's rows for this dispatch's top nodes (t0 ..), objects per row.
layout(std430, binding = 2) readonly buffer Mask { uint object_mask[]; };
layout(std430, binding = 3) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = 4) writeonly buffer Flags { uint flags[]; };
layout(std430, binding = 5) writeonly buffer Values { uint values[]; };
layout(std430, binding = 6) writeonly buffer Tested { uint tested[]; };
// A level's nodes and the CSR offsets of their children grow with the rays: paged.
PAGED_BUFFER(readonly, Nodes, ConeNode, 7)
PAGED_LOAD(Nodes, ConeNode)
PAGED_BUFFER(readonly, First, uint, 11)
PAGED_LOAD(First, uint)
layout(push_constant) uniform Push {
  uint phase, count, t0, b0, tris, objects, use_mask, base_up, base, children_max;
  float eps;
  uint id_base;  // phase 0: packed node ids relative to this node (a dispatch may cover part of a block)
  uint node_page, first_page;
} pc;

ConeNode NodeAt(uint i) { return LoadNodes(i, pc.node_page); }

const uint kTriBits = 14u, kTriMask = (1u << 14) - 1u;

void main() {
  const uint e = GlobalIndex();
  if (e >= pc.count) return;
  if (pc.phase == 0u) {
    const uint node = pc.t0 + e / pc.tris, tri = pc.b0 + e % pc.tris;
    const bool test = pc.use_mask == 0u || object_mask[(node - pc.t0) * pc.objects + info[tri].ids.y] != 0u;
    tested[e] = test ? 1u : 0u;
    // Fault 1: the top level ignores the triangle sphere's radius (a too-small bound).
    vec4 sphere = tri_spheres[tri];
    if (kFault == 1u) sphere.w = 0.0;
    flags[e] = (test && ConeTest(NodeAt(node), sphere, pc.eps)) ? 1u : 0u;
    values[e] = ((node - pc.id_base) << kTriBits) | (tri - pc.b0);
  } else if (pc.phase == 2u) {
    // Fault 2 (seen only when the mask is computed in parts, --split-bytes): the part's start is dropped.
    const uint g = (kFault == 2u ? 0u : pc.t0) + e;  // element of the whole mask; this dispatch writes a part of it
    flags[e] = ConeTest(NodeAt(g / pc.objects), tri_spheres[g % pc.objects], pc.eps) ? 1u : 0u;
  } else {
    const uint parent = pc.base_up + (pairs[e] >> kTriBits), tri_local = pairs[e] & kTriMask;
    const vec4 sphere = tri_spheres[pc.b0 + tri_local];
    const uint c0 = LoadFirst(parent, pc.first_page), c1 = LoadFirst(parent + 1u, pc.first_page);
    tested[e] = c1 - c0;
    for (uint k = 0u; k < pc.children_max; ++k) {
      flags[e * pc.children_max + k] = 0u;
      values[e * pc.children_max + k] = 0u;
    }
    for (uint c = c0; c < c1; ++c) {
      const uint slot = e * pc.children_max + (c - c0);
      flags[slot] = ConeTest(NodeAt(c), sphere, pc.eps) ? 1u : 0u;
      values[slot] = ((c - pc.base) << kTriBits) | tri_local;
    }
  }
}
