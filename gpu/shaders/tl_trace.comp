#version 460
// tl.trace: one invocation per ray walks the traversal list of its direction class without a stack
// (Toczek et al.'s loop): a triangle is tested and the walk moves on by its escape; a sphere the ray
// may meet before its best hit leads to its first child (the next element), a missed one to its
// escape; 0 and -1 end the walk. With cull, triangles are one-sided: only a front hit counts.
// Steps run in blocks of kTlLoopBlock (lavapipe ends a loop after
// 65,535 iterations) and every step moves forward, so a walk ends within its list. Closest hits keep
// the packed (t, id) minimum, so ties resolve as every other tracer's do. Mirrors emu PassTlTrace.
#include "common.glsl"
#define TL_FLIPPED_SPHERE_TEST (kFault == 2u)
#include "tl.glsl"
#define WATERTIGHT_SWAP_FAULT 0xFFFFFFFFu  // no range-swap fault here
#include "watertight.glsl"

layout(std430, binding = kTlTraceBindFirst) readonly buffer First { uint first[]; };
layout(std430, binding = kTlTraceBindEscapes) readonly buffer Escapes { int escapes[]; };
layout(std430, binding = kTlTraceBindWords) readonly buffer Words { uvec4 words[]; };
layout(std430, binding = kTlTraceBindVertices) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = kTlTraceBindRays) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = kTlTraceBindHits) writeonly buffer Hits { uint64_t hits[]; };
layout(std430, binding = kTlTraceBindOccluded) writeonly buffer Occluded { uint occluded[]; };
layout(std430, binding = kTlTraceBindSpheres) writeonly buffer SphereTests { uint sphere_tests[]; };
layout(std430, binding = kTlTraceBindTriangles) writeonly buffer TriangleTests { uint triangle_tests[]; };
layout(std430, binding = kTlTraceBindTriWords) readonly buffer TriWords { uvec4 tri_words[]; };
layout(std430, binding = kTlTraceBindWindows) readonly buffer Windows { uint windows[]; };
layout(push_constant) uniform Block { TlTracePush pc; };

const uint64_t kMiss = 0xFFFFFFFFFFFFFFFFul;
const uint kNoCase = 0xFFFFFFFFu;

// The ray's case on its triangle (emu tl::RayCase): 2 * ends + behind, or kNoCase (no triangle, a
// sliver, or a direction within kTlSideRatio of the plane).
uint RayCase(const Ray r, bool ends, uint K, uint k) {
  const uint prim = r.info.y;
  if (prim >= pc.triangles) return kNoCase;
  const uvec4 w = tri_words[prim];
  const vec3 v0 = vertices[w.x].xyz;
  precise const vec3 e1 = vertices[w.y].xyz - v0, e2 = vertices[w.z].xyz - v0;
  const vec3 n = Cross3(e1, e2);
  precise const float na = MaxAbs(n, n) * 32.0, nb = MaxAbs(e1, e1) * MaxAbs(e2, e2);
  if (!(na >= nb)) return kNoCase;
  const vec3 d = r.direction_tmax.xyz;
  const float dn = Dot3(d, n);
  precise const float lim = kTlSideRatio * (Length3(d) * Length3(n));
  if (!(abs(dn) > lim)) return kNoCase;
  const bool behind = ends ? dn > 0.0 : dn < 0.0;
  // Regular windows hold what lies past the triangle along the class's facets: only for a ray whose
  // own point (its origin, or its end for an ending ray) lies within the triangle's bounds there
  // (a G-buffer point may lie just outside its triangle, in its plane).
  if (pc.heads == kTlHeadsRegular) {
    precise const vec3 p = ends ? r.origin_tmin.xyz + d * r.direction_tmax.w : r.origin_tmin.xyz;
    vec3 m[4];
    const uint facets = TlFacets(K, k, m);
    for (uint j = 0u; j < facets; ++j) {
      const float bound = TlFacetBound(m[j], v0, vertices[w.y].xyz, vertices[w.z].xyz, ends);
      const float x = Dot3(m[j], p);
      if (ends ? !(x <= bound) : !(x >= bound)) return kNoCase;
    }
  }
  // Fault 5: the window of the other side.
  return (ends ? 2u : 0u) + ((behind != (kFault == 5u)) ? 1u : 0u);
}

void main() {
  const uint ray = GlobalIndex();
  if (ray >= pc.count) return;
  const Ray r = rays[ray];
  const vec3 org = r.origin_tmin.xyz, dir = r.direction_tmax.xyz;
  const float tmin = r.origin_tmin.w, tmax = r.direction_tmax.w;
  const uint K = pc.lists;
  uint k = TlListFor(K, dir);
  // Fault 3: the ray walks the list of the opposite direction (the other of each pair).
  if (kFault == 3u && K > 1u) k = K == 8u ? 7u - k : k ^ 1u;
  uint i = first[k];
  uint end = first[k + 1u];
  // A ray on a triangle walks that triangle's window (tl.heads) for its case; an eye ray its
  // cell's (tl.cells; a cell beyond the windows: the whole list).
  if (pc.heads == kTlHeadsCells) {
    // Fault 6: an eye ray walks the window of the next cell.
    const uint cell = r.info.w + (kFault == 6u ? 1u : 0u);
    if (cell < pc.triangles) {
      i = windows[2u * (cell * K + k)];
      end = windows[2u * (cell * K + k) + 1u];
    }
  } else {
    const uint cs = pc.heads != kTlHeadsOff ? RayCase(r, pc.shadow != 0u, K, k) : kNoCase;
    if (cs != kNoCase) {
      const uint w = 2u * ((r.info.y * kTlCases + cs) * K + k);
      i = windows[w];
      end = windows[w + 1u];
    }
  }
  uint64_t best = kMiss;
  uint spheres = 0u, triangles = 0u;
  bool done = i >= end;
  for (uint b = 0u; !done && b <= end / kTlLoopBlock; ++b) {
    for (uint j = 0u; !done && j < kTlLoopBlock; ++j) {
      int next = escapes[i];
      const uvec4 w = words[i];
      if (next == 1 || next == 0) {
        ++triangles;
        float t, det;
        // One-sided (cull): a triangle met from behind is no hit. Fault 4: the back is kept instead.
        if (w.w != r.info.y &&
            WatertightSided(org, dir, vertices[w.x].xyz, vertices[w.y].xyz, vertices[w.z].xyz, tmin, tmax, t, det) &&
            (pc.cull == 0u || (kFault == 4u ? det < 0.0 : det > 0.0))) {
          const uint64_t packed = (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(w.w);
          if (packed < best) best = packed;
          if (pc.shadow != 0u) next = 0;
        }
      } else {
        ++spheres;
        const float limit = best == kMiss ? tmax : uintBitsToFloat(uint(best >> 32));
        if (TlSphereMayHit(org, dir, tmin, limit, uintBitsToFloat(w))) next = 1;
        // Fault 1: a missed sphere's escape one element short.
        else if (kFault == 1u && next > 2) next -= 1;
      }
      i += uint(next);
      done = next <= 0 || i >= end;
    }
  }
  if (pc.shadow != 0u)
    occluded[ray] = best != kMiss ? 1u : 0u;
  else
    hits[ray] = best;
  sphere_tests[ray] = spheres;
  triangle_tests[ray] = triangles;
}
