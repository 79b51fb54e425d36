#version 460
// Mirror rays (thesis eqs. 3.3-3.4) where the material reflects; mirrors emu PassRaygenReflection.
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
  const float kr = materials[sf.info.z].diffuse_reflectivity.w;
  if (!(kr > 0.0)) return;
  const vec3 i = sf.incoming.xyz, n = sf.normal.xyz;
  const float ni = Dot3(n, i);
  // Fault 1: the factor 2 of the mirror formula is lost.
  precise const float k = kFault == 1u ? ni : 2.0 * ni;
  // Fault 2: the normal term is added, not subtracted (a wrong operand: the ray goes into the surface).
  precise const vec3 d = kFault == 2u ? vec3(i.x + n.x * k, i.y + n.y * k, i.z + n.z * k)
                                      : vec3(i.x - n.x * k, i.y - n.y * k, i.z - n.z * k);
  if (!(Dot3(d, d) > 0.0)) return;
  // Fault 3: the ray starts at tmin 0, so it may hit the surface it leaves.
  r.origin_tmin = vec4(sf.position.xyz, kFault == 3u ? 0.0 : fc.params.x);
  r.direction_tmax = vec4(d, uintBitsToFloat(0x7F800000u));  // +inf
  r.info = uvec4(sf.info.y, sf.info.x, kRayReflection, pc.base + s);
  precise const vec4 w = vec4(sf.weight.x * kr, sf.weight.y * kr, sf.weight.z * kr, 0.0);
  r.weight = w;
  rays[s] = r;
  flags[s] = 1u;
}
