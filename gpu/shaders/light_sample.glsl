// Where sample k of a light lies for one shading point (docs/area-lights.md); mirrors
// emu/include/rayspace/emu/light_sample.h operation for operation. Needs common.glsl (Sqrt). A kernel
// defines LIGHT_SAMPLE_RADIUS_FAULT to plant "the radius is not square-rooted" as that fault.
#ifndef LIGHT_SAMPLE_RADIUS_FAULT
#define LIGHT_SAMPLE_RADIUS_FAULT 0u
#endif

vec3 LightSamplePoint(Light light, uint index, uint key, uint k) {
  const vec3 c = light.position.xyz;
  const uint shape = light.sampling.x;
  if (shape == kLightPoint) return c;
  const vec2 ab = StratifiedPoint(key, index, k, light.sampling.w, light.axis_u.w, light.axis_v.w);
  const vec3 u = light.axis_u.xyz, v = light.axis_v.xyz;
  if (shape == kLightRect) {
    precise const float x = ab.x * 2.0 - 1.0, y = ab.y * 2.0 - 1.0;
    precise const vec3 p = vec3((c.x + x * u.x) + y * v.x, (c.y + x * u.y) + y * v.y, (c.z + x * u.z) + y * v.z);
    return p;
  }
  const vec2 cs = UnitCircle(ab.y);
  if (shape == kLightDisk) {
    const float r = (LIGHT_SAMPLE_RADIUS_FAULT != 0u && kFault == LIGHT_SAMPLE_RADIUS_FAULT) ? ab.x : Sqrt(ab.x);
    precise const float x = r * cs.x, y = r * cs.y;
    precise const vec3 p = vec3((c.x + x * u.x) + y * v.x, (c.y + x * u.y) + y * v.y, (c.z + x * u.z) + y * v.z);
    return p;
  }
  precise const float z = 1.0 - ab.x * 2.0;
  precise const float zz = 1.0 - z * z;
  const float rr = (LIGHT_SAMPLE_RADIUS_FAULT != 0u && kFault == LIGHT_SAMPLE_RADIUS_FAULT) ? zz : Sqrt(zz);
  const float radius = light.position.w;
  precise const vec3 p = vec3(c.x + radius * (rr * cs.x), c.y + radius * (rr * cs.y), c.z + radius * z);
  return p;
}
