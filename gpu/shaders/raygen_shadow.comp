#version 460
// Shadow rays (thesis eqs. 3.1-3.2), one invocation per surface slot; mirrors emu PassRaygenShadow.
#include "common.glsl"
#define LIGHT_SAMPLE_RADIUS_FAULT 5u  // Fault 5: a disk's or sphere's sample radius is not square-rooted
#include "light_sample.glsl"

layout(std430, binding = kRaygenBindSurfaces) readonly buffer Surfaces { Surface surfaces[]; };
layout(std430, binding = kRaygenBindLightsOrMaterials) readonly buffer Lights { Light lights[]; };
layout(std430, binding = kRaygenBindFrame) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = kRaygenBindRays) writeonly buffer Rays { Ray rays[]; };
layout(std430, binding = kRaygenBindFlags) writeonly buffer Flags { uint flags[]; };
layout(push_constant) uniform Block { RaygenShadowPush pc; };

const float kFloatMax = 3.40282347e38;

void main() {
  const uint s = GlobalIndex();
  if (s >= pc.surface_count) return;
  const Surface sf = surfaces[s];
  for (uint j = 0; j < pc.slots; ++j) {
    const uint slot = s * pc.slots + j;
    Ray r;
    r.origin_tmin = vec4(0.0);
    r.direction_tmax = vec4(0.0);
    r.info = uvec4(0u);
    r.weight = vec4(0.0);
    rays[slot] = r;
    flags[slot] = 0u;
  }
  if (sf.position.w == 0.0) return;
  const vec3 p = sf.position.xyz;
  // Fault 6: the sampler's key ignores the primitive (the bounces of a pixel draw the same points).
  const uint key = SamplerKey(sf.info.y, kFault == 6u ? 0u : sf.info.x);
  // Fault 3: the last light of every surface is skipped (a lost tail).
  const uint lights_used = kFault == 3u ? pc.light_count - 1u : pc.light_count;
  for (uint l = 0; l < lights_used; ++l) {
    const Light light = lights[l];
    for (uint k = 0; k < light.sampling.y; ++k) {
      // The ray starts at the light, at one of an area light's sample points (light_sample.glsl).
      // Fault 4: an area light's sample is drawn at the next sample's point.
      const vec3 o = LightSamplePoint(light, l, key, kFault == 4u ? k + 1u : k);
      precise const vec3 v = p - o;
      const float dist = Length3(v);
      if (!(dist > 0.0) || !(abs(v.x) <= kFloatMax && abs(v.y) <= kFloatMax && abs(v.z) <= kFloatMax)) continue;
      precise const vec3 d = vec3(Div(v.x, dist), Div(v.y, dist), Div(v.z, dist));
      // kShadowRuleLit: only where the light is in front (n.l > 0 with n turned to the viewer, as shade.comp).
      if (pc.rule == kShadowRuleLit) {
        vec3 n = sf.normal.xyz;
        if (Dot3(n, sf.incoming.xyz) > 0.0) n = -n;
        if (!(Dot3(-d, n) > 0.0)) continue;
      }
      // Fault 1: the shadow ray runs all the way to the surface (no tmax shortening).
      precise const float tmax = kFault == 1u ? dist : dist * fc.params.z;
      Ray r;
      r.origin_tmin = vec4(o, fc.params.x);
      r.direction_tmax = vec4(d, tmax);
      // Fault 2: the ray is credited to the next pixel (an off-by-one in an id).
      r.info = uvec4(sf.info.y + (kFault == 2u ? 1u : 0u), sf.info.x, kRayShadow, l);
      r.weight = sf.weight;
      const uint slot = s * pc.slots + light.sampling.z + k;
      rays[slot] = r;
      flags[slot] = 1u;
    }
  }
}
