#version 460
// Final ray-triangle tests on surviving level-1 pairs; mirrors emu PassIntersect (watertight inside
// test, plane distance, closest hit by 64-bit atomic minimum, shadow rays by atomic store).
// Fault 2 (seen only when the ray arrays span several pages, --split-bytes): every paged load reads
// the first page.
#define PAGED_FAULT 2u
#include "common.glsl"
#extension GL_EXT_shader_atomic_int64 : require
#include "paged.glsl"

// pairs and tests hold this dispatch's part of the pair stream; the rest is read or written anywhere
// (by leaf node, sorted position and ray), so it is paged.
layout(std430, binding = kIntersectBindPairs) readonly buffer Pairs { uint pairs[]; };
layout(std430, binding = kIntersectBindTriangles) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = kIntersectBindTests) writeonly buffer Tests { uint tests[]; };
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


bool Watertight(vec3 org, vec3 dir, vec3 v0, vec3 v1, vec3 v2, float tmin, float tmax, out float t_out) {
  const vec3 a = abs(dir);
  int kz = 0;
  if (a.y > a[kz]) kz = 1;
  if (a.z > a[kz]) kz = 2;
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (dir[kz] < 0.0) {
    const int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  precise const float sx = Div(dir[kx], dir[kz]), sy = Div(dir[ky], dir[kz]);
  precise const vec3 A0 = v0 - org, B0 = v1 - org, C0 = v2 - org;
  const float ka = InversePowerOfTwo(max(MaxAbs(A0, B0), MaxAbs(C0, C0)));
  precise const vec3 A = A0 * ka, B = B0 * ka, C = C0 * ka;
  precise const float ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
  precise const float bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
  precise const float cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
  precise const float u = cx * by - cy * bx;
  precise const float v = ax * cy - ay * cx;
  precise const float w = bx * ay - by * ax;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  precise const float det = (u + v) + w;
  if (det == 0.0) return false;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  const float ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const vec3 n0 = Cross3(e1 * ke, e2 * ke);
  const float kn = InversePowerOfTwo(MaxAbs(n0, n0));
  precise const vec3 n = n0 * kn;
  precise const float t0 = Div(Dot3(A0, n), Dot3(dir, n));
  // kFaultUlp4: t four ULP too far, beyond what any conformant device computes.
  const float t = kFault == kFaultUlp4 ? uintBitsToFloat(floatBitsToUint(t0) + 4u) : t0;
  // Fault 1: tmin and tmax swapped in the range check (every hit rejected).
  if (kFault == 1u ? !(t > tmax && t < tmin) : !(t > tmin && t < tmax)) return false;
  t_out = t;
  return true;
}

void main() {
  const uint p = GlobalIndex();
  if (p >= pc.count) return;
  const uint node = pc.base1 + (pairs[p] >> kPairTriangleBits), prim = pc.b0 + (pairs[p] & kPairTriangleMask);
  const Triangle tri = triangles[prim];
  const uint f0 = LoadFirst(node, pc.first_page), f1 = LoadFirst(node + 1u, pc.first_page);
  tests[p] = f1 - f0;
  for (uint j = f0; j < f1; ++j) {
    const uint ray = LoadOrder(j, pc.order_page);
    const Ray r = LoadRays(ray, pc.ray_page);
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
}
