#version 460
// Refracted rays (thesis eqs. 3.5-3.7), none on total internal reflection; mirrors emu
// PassRaygenRefraction.
#include "common.glsl"

layout(std430, binding = kRaygenBindSurfaces) readonly buffer Surfaces { Surface surfaces[]; };
layout(std430, binding = kRaygenBindLightsOrMaterials) readonly buffer Materials { Material materials[]; };
layout(std430, binding = kRaygenBindFrame) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = kRaygenBindRays) writeonly buffer Rays { Ray rays[]; };
layout(std430, binding = kRaygenBindFlags) writeonly buffer Flags { uint flags[]; };
layout(push_constant) uniform Block { RaygenPush pc; };  // surfaces base .. base + count - 1

void main() {
  const uint s = GlobalIndex();
  if (s >= pc.surface_count) return;
  Ray r;
  r.origin_tmin = vec4(0.0);
  r.direction_tmax = vec4(0.0);
  r.info = uvec4(0u);
  r.weight = vec4(0.0);
  rays[s] = r;
  flags[s] = 0u;
  const Surface sf = surfaces[s];
  if (sf.position.w == 0.0) return;
  const Material m = materials[sf.info.z];
  const float kt = m.transparency_ior.x;
  if (!(kt > 0.0)) return;
  const vec3 i = sf.incoming.xyz;
  vec3 n = sf.normal.xyz;
  float cosi = Dot3(i, n);
  precise float ri = Div(1.0, m.transparency_ior.y);
  // Fault 1: the ratio is not inverted when the ray leaves the medium.
  if (cosi > 0.0) {
    // Fault 2: the normal is not turned to face the ray when it leaves the medium.
    if (kFault != 2u) n = -n;
    cosi = -cosi;
    ri = kFault == 1u ? ri : m.transparency_ior.y;
  }
  // Fault 3: the ratio's square is lost from Snell's law under the root (a dropped factor).
  precise const float k = kFault == 3u ? 1.0 - (1.0 - cosi * cosi) : 1.0 - (ri * ri) * (1.0 - cosi * cosi);
  if (k < 0.0) return;
  precise const float a = ri * cosi + Sqrt(k);
  precise const vec3 d = vec3(i.x * ri - n.x * a, i.y * ri - n.y * a, i.z * ri - n.z * a);
  if (!(Dot3(d, d) > 0.0)) return;
  r.origin_tmin = vec4(sf.position.xyz, fc.params.x);
  r.direction_tmax = vec4(d, uintBitsToFloat(0x7F800000u));
  r.info = uvec4(sf.info.y, sf.info.x, kRayRefraction, pc.base + s);
  precise const vec4 w = vec4(sf.weight.x * kt, sf.weight.y * kt, sf.weight.z * kt, 0.0);
  r.weight = w;
  rays[s] = r;
  flags[s] = 1u;
}
