#version 460
// intersect.tree: the final tests of the joint descent, one invocation per final pair: the rays of
// a level-1 node (first1 over the sorted order) or the one ray of a level-0 pair against the pair's
// triangle; closest hit by 64-bit atomic minimum, shadow rays by atomic store. Mirrors emu
// PassIntersectTree.
#include "common.glsl"
#extension GL_EXT_shader_atomic_int64 : require
#define WATERTIGHT_SWAP_FAULT 2u  // fault 2
#include "watertight.glsl"

layout(std430, binding = kIntersectTreeBindPairCone) readonly buffer PairCone { uint pair_cone[]; };
layout(std430, binding = kIntersectTreeBindPairItem) readonly buffer PairItem { uint pair_item[]; };
layout(std430, binding = kIntersectTreeBindFirst) readonly buffer First { uint first1[]; };
layout(std430, binding = kIntersectTreeBindTreeTriangles) readonly buffer TreeTriangles { uint tree_triangles[]; };
layout(std430, binding = kIntersectTreeBindOrder) readonly buffer Order { uint order[]; };
layout(std430, binding = kIntersectTreeBindRays) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = kIntersectTreeBindTriangles) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = kIntersectTreeBindTests) writeonly buffer Tests { uint tests[]; };
layout(std430, binding = kIntersectTreeBindHits) buffer Hits { uint64_t hits[]; };
layout(std430, binding = kIntersectTreeBindOccluded) buffer Occluded { uint occluded[]; };
layout(push_constant) uniform Block { IntersectTreePush pc; };

void main() {
  const uint p = GlobalIndex();
  if (p >= pc.count) return;
  const uint L = pair_cone[p] >> kTreeLevelShift, n = pair_cone[p] & kTreeNodeMask;
  const uint j0 = L == 1u ? first1[n] : n;
  // Fault 1: a level-1 node's rays after its first are skipped.
  const uint j1 = L == 1u && kFault != 1u ? first1[n + 1u] : j0 + 1u;
  const uint prim = tree_triangles[pair_item[p] & ~kTreeItemTriangle];
  const Triangle tri = triangles[prim];
  // Fault 3: each pair reports one test.
  tests[p] = kFault == 3u ? 1u : j1 - j0;
  for (uint j = j0; j < j1; ++j) {
    const uint ray = order[j];
    const Ray r = rays[ray];
    if (prim == r.info.y) continue;
    float th;
    if (!Watertight(r.origin_tmin.xyz, r.direction_tmax.xyz, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, r.origin_tmin.w,
                    r.direction_tmax.w, th))
      continue;
    if (pc.shadow != 0u) {
      atomicExchange(occluded[ray], 1u);
    } else {
      const uint64_t packed = (uint64_t(floatBitsToUint(th)) << 32) | uint64_t(prim);
      atomicMin(hits[ray], packed);
    }
  }
}
