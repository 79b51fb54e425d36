#version 460
// Shading (thesis eq. 3.19) into the 64-bit fixed-point accumulator; mirrors emu PassShade.
#include "common.glsl"
#include "paged.glsl"
#include "light_sample.glsl"
#extension GL_EXT_shader_atomic_int64 : require

layout(std430, binding = kShadeBindSurfaces) readonly buffer Surfaces { Surface surfaces[]; };
layout(std430, binding = kShadeBindShadowFlags) readonly buffer ShadowFlags { uint shadow_flags[]; };
layout(std430, binding = kShadeBindShadowOffsets) readonly buffer ShadowOffsets { uint shadow_offsets[]; };
layout(std430, binding = kShadeBindMaterials) readonly buffer Materials { Material materials[]; };
layout(std430, binding = kShadeBindLights) readonly buffer Lights { Light lights[]; };
// Indexed by dense shadow ray and by pixel, in any order: paged (kShadeBindOccluded and kShadeBindAccum, four bindings each).
PAGED_BUFFER(readonly, Occluded, uint, kShadeBindOccluded)
PAGED_LOAD(Occluded, uint)
PAGED_BUFFER(, Accum, uint64_t, kShadeBindAccum)
PAGED_ATOMIC(atomicAdd, Accum, uint64_t)
layout(push_constant) uniform Block { ShadePush pc; };

uint64_t ToFixed(float c) {
  const float v = min(max(c, 0.0), kAccumMax);
  precise const float s = v * kAccumScale;
  return uint64_t(s);
}

void main() {
  const uint s = GlobalIndex();
  if (s >= pc.surface_count) return;
  const Surface sf = surfaces[s];
  if (sf.position.w == 0.0) return;
  const Material m = materials[sf.info.z];
  const vec3 p = sf.position.xyz, view = sf.incoming.xyz;
  vec3 n = sf.normal.xyz;
  if (Dot3(n, view) > 0.0) n = -n;
  const uint shininess = uint(m.specular_shininess.w);
  const uint key = SamplerKey(sf.info.y, sf.info.x);
  precise vec3 color = vec3(0.0);
  for (uint l = 0u; l < pc.light_count; ++l) {
    const Light light = lights[l];
    for (uint k = 0u; k < light.sampling.y; ++k) {
      const uint slot = s * pc.slots + light.sampling.z + k;
      if (shadow_flags[slot] == 0u || LoadOccluded(shadow_offsets[slot], pc.occluded_page) != 0u) continue;
      // The light, or one of an area light's samples. Fault 4: lit from the next sample's point.
      const vec3 q = LightSamplePoint(light, l, key, kFault == 4u ? k + 1u : k);
      // Fault 2: the light vector points from the light to the surface (swapped operands).
      precise const vec3 lv = kFault == 2u ? p - q : q - p;
      const float dist = Length3(lv);
      precise const vec3 ldir = vec3(Div(lv.x, dist), Div(lv.y, dist), Div(lv.z, dist));
      // Fault 1: the quadratic attenuation term uses the distance instead of its square.
      precise const float dd = kFault == 1u ? dist : dist * dist;
      precise const float att = Div(1.0, (light.attenuation.x + dist * light.attenuation.y) + dd * light.attenuation.z);
      const float ndl = Dot3(ldir, n);
      if (!(ndl > 0.0)) continue;
      const float diffuse = max(0.0, min(1.0, ndl));
      precise const vec3 hv = ldir - view;
      const vec3 h = Normalize3(hv);
      const float specular = max(0.0, min(1.0, IntPow(max(0.0, Dot3(h, n)), shininess)));
      // 1 / samples. Fault 5: an area light's samples are not divided by their count.
      const float share = kFault == 5u ? 1.0 : light.attenuation.w;
      for (int c = 0; c < 3; ++c) {
        const float li = light.color_intensity[c];
        precise float a = ((((m.diffuse_reflectivity[c] * li) * diffuse) * light.color_intensity.w) * att) * share;
        color[c] = color[c] + a;
        precise float b = ((((m.specular_shininess[c] * li) * specular) * light.color_intensity.w) * att) * share;
        color[c] = color[c] + b;
      }
    }
  }
  const uint pixel = sf.info.y;
  // Fault 3: the blue channel is never accumulated (a loop bound one short).
  for (int k = 0; k < (kFault == 3u ? 2 : 3); ++k) {
    precise const float c = color[k] * sf.weight[k];
    const uint64_t q = ToFixed(c);
    if (q != 0ul) atomicAddAccum(3u * pixel + uint(k), pc.accum_page, q);
  }
}
