#version 460
// Shading points of a later generation, one invocation per traced ray; mirrors emu
// PassSurfacesFromHits (hit point o + t d, barycentric shading normal).
#include "common.glsl"
#include "shading_normal.glsl"

layout(std430, binding = kSurfacesHitsBindRays) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = kSurfacesHitsBindHits) readonly buffer Hits { uvec2 hits[]; };  // (primitive, t bits): little-endian uint64
layout(std430, binding = kSurfacesHitsBindTriangles) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = kSurfacesHitsBindNormals) readonly buffer Normals { TriangleNormals normals[]; };
layout(std430, binding = kSurfacesHitsBindInfo) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = kSurfacesHitsBindSurfaces) writeonly buffer Surfaces { Surface surfaces[]; };
layout(push_constant) uniform Block { SurfacesHitsPush pc; };

void main() {
  const uint i = GlobalIndex();
  if (i >= pc.n) return;
  const Ray r = rays[i];
  const uvec2 h = hits[i];
  Surface s;
  s.position = vec4(0.0);
  s.normal = vec4(0.0);
  s.incoming = vec4(0.0);
  s.weight = vec4(0.0);
  if (h.x != 0xFFFFFFFFu || h.y != 0xFFFFFFFFu) {
    const uint prim = h.x;
    const float t = uintBitsToFloat(h.y);
    const vec3 o = r.origin_tmin.xyz, d = r.direction_tmax.xyz;
    // Fault 1: the hit point is taken at t from the ray's tmin instead of its origin.
    const float tt = kFault == 1u ? t + r.origin_tmin.w : t;
    precise const vec3 p = vec3(o.x + tt * d.x, o.y + tt * d.y, o.z + tt * d.z);
    s.position = vec4(p, 1.0);
    s.normal = vec4(ShadingNormalOf(triangles[prim], normals[prim], p), 0.0);
    s.incoming = vec4(Normalize3(d), 0.0);
    // Fault 2: the ray's weight is not carried (every surface weighs 1).
    s.weight = kFault == 2u ? vec4(1.0, 1.0, 1.0, 0.0) : r.weight;
    // Fault 3: the pixel is taken from the surface the ray left, not the ray's pixel (a swapped field).
    s.info = uvec4(prim, kFault == 3u ? r.info.y : r.info.x, info[prim].ids.x, 0u);
  } else {
    s.info = uvec4(kNoPrim, r.info.x, 0u, 0u);
  }
  surfaces[i] = s;
}
