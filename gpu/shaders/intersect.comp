#version 460
// Final ray-triangle tests on surviving level-1 pairs; mirrors emu PassIntersect (watertight inside
// test, plane distance, closest hit by 64-bit atomic minimum, shadow rays by atomic store).
// Fault 2 (seen only when the ray arrays span several pages, --split-bytes): every paged load reads
// the first page.
#define PAGED_FAULT 2u
#include "common.glsl"
#include "cone.glsl"
#extension GL_EXT_shader_atomic_int64 : require
#include "paged.glsl"
#define WATERTIGHT_SWAP_FAULT 1u  // fault 1
#include "watertight.glsl"

// pairs and tests hold this dispatch's part of the pair stream; the rest is read or written anywhere
// (by leaf node, sorted position and ray), so it is paged.
layout(std430, binding = kIntersectBindPairs) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = kIntersectBindTriangles) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = kIntersectBindTests) writeonly buffer Tests { uint tests[]; };
layout(std430, binding = kIntersectBindTriSpheres) readonly buffer TriSpheres { vec4 tri_spheres[]; };
PAGED_BUFFER(readonly, First, uint, kIntersectBindFirst)
PAGED_LOAD(First, uint)
PAGED_BUFFER(readonly, Order, uint, kIntersectBindOrder)
PAGED_LOAD(Order, uint)
PAGED_BUFFER(readonly, Rays, Ray, kIntersectBindRays)
PAGED_LOAD(Rays, Ray)
PAGED_BUFFER(, Hits, uint64_t, kIntersectBindHits)
PAGED_ATOMIC(atomicMin, Hits, uint64_t)
PAGED_BUFFER(, Occluded, uint, kIntersectBindOccluded)
PAGED_ATOMIC(atomicExchange, Occluded, uint)
layout(push_constant) uniform Block { IntersectPush pc; };

// kLeafTestRaySphere: the ray as a one-ray node (emu cone::RayMayMeetSphere) under the cone test.
bool RayMayMeetSphere(Ray r, vec4 sphere) {
  ConeNode n;
  n.sphere = vec4(r.origin_tmin.xyz, 0.0);
  n.cone = vec4(Normalize3(r.direction_tmax.xyz), 1.0);
  n.extra = vec4(0.0, 1.0, 0.0, 0.0);
  return ConeTest(Finish(n), sphere, pc.eps);
}

void Pair(uint p) {
  const uint node = pc.base1 + (pairs[p] >> kPairTriangleBits), prim = pc.b0 + (pairs[p] & kPairTriangleMask);
  const Triangle tri = triangles[prim];
  const uint f0 = LoadFirst(node, pc.first_page), f1 = LoadFirst(node + 1u, pc.first_page);
  const bool sphere_first = pc.leaf_test == kLeafTestRaySphere;
  const vec4 sphere = sphere_first ? tri_spheres[prim] : vec4(0.0);
  uint performed = 0u;
  // Fault 3: a node's last ray is never tested (a lost tail).
  const uint last = kFault == 3u && f1 > f0 ? f1 - 1u : f1;
  for (uint j = f0; j < last; ++j) {
    const uint ray = LoadOrder(j, pc.order_page);
    const Ray r = LoadRays(ray, pc.ray_page);
    if (sphere_first && !RayMayMeetSphere(r, sphere)) continue;
    ++performed;
    if (prim == r.info.y) continue;
    float th;
    if (!Watertight(r.origin_tmin.xyz, r.direction_tmax.xyz, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, r.origin_tmin.w,
                    r.direction_tmax.w, th))
      continue;
    if (pc.shadow != 0u) {
      atomicExchangeOccluded(ray, pc.occluded_page, 1u);
    } else {
      const uint64_t packed = (uint64_t(floatBitsToUint(th)) << 32) | uint64_t(prim);
      atomicMinHits(ray, pc.hit_page, packed);
    }
  }
  // Fault 3 counts the lost ray as tested, as the node's ray count (only the hits show the fault).
  tests[p] = sphere_first ? performed : f1 - f0;
}

// A grid of at most kIntersectGroups workgroups (gpu/src/intersect.cpp) strides over the pairs:
// lavapipe pays for every workgroup it starts.
void main() {
  const uint stride = gl_NumWorkGroups.x * gl_NumWorkGroups.y * kLocalSize;
  for (uint p = GlobalIndex(); p < pc.count; p += stride) Pair(p);
}
