#version 460
// Raster fragment stage: depth from the pixel-centre ray and the triangle's plane, written as
// gl_FragDepth, and the primitive id (emu raster::ShadeFragment).
#extension GL_GOOGLE_include_directive : require
#extension GL_ARB_gpu_shader_int64 : require
#include "rayspace/contract.h"

layout(std430, binding = 0) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 1) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = 2) readonly buffer Normals { TriangleNormals normals[]; };
layout(std430, binding = 3) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = 4) readonly buffer Materials { Material materials[]; };
layout(location = 0) flat in uint v_prim;  // the triangle (raster.vert)
layout(location = 0) out vec4 out_diffuse;
layout(location = 1) out vec4 out_specular;
layout(location = 2) out vec4 out_position;
layout(location = 3) out vec4 out_normal;
layout(location = 4) out uint out_prim;
layout(constant_id = 0) const uint kFault = 0;  // planted fault (0 = none)
layout(constant_id = 2) const bool kStrictMath = false;  // --strict-math
#include "div_sqrt.glsl"

float Dot3(vec3 a, vec3 b) {
  precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
  return r;
}

vec3 Cross3(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return r;
}
vec3 Normalize3(vec3 v) {
  const float l = Sqrt(Dot3(v, v));
  precise vec3 r = vec3(Div(v.x, l), Div(v.y, l), Div(v.z, l));
  return r;
}

// emu InversePowerOfTwo / MaxAbs (common.glsl is compute-only).
float InversePowerOfTwo(float m) {
  const int e = int((floatBitsToUint(m) >> 23) & 0xFFu);
  return uintBitsToFloat(uint(clamp(254 - e, 1, 254)) << 23);
}
float MaxAbs(vec3 a, vec3 b) {
  return max(max(max(abs(a.x), abs(a.y)), abs(a.z)), max(max(abs(b.x), abs(b.y)), abs(b.z)));
}

#include "shading_normal.glsl"

vec3 ShadingNormal(uint prim, vec3 p) { return ShadingNormalOf(triangles[prim], normals[prim], p); }

void main() {
  const uint prim = v_prim;
  const Triangle t = triangles[prim];
  const uint px = uint(gl_FragCoord.x), py = uint(gl_FragCoord.y);
  precise vec3 d;
  // Fault 3: the pixel's column steps along the rows and its row along the columns (a swapped index).
  const uint sx = kFault == 3u ? py : px, sy = kFault == 3u ? px : py;
  for (int k = 0; k < 3; ++k) {
    precise float a = float(sx) * fc.pixel_dx[k];
    precise float b = fc.pixel_origin[k] + a;
    precise float c = float(sy) * fc.pixel_dy[k];
    d[k] = b + c;
  }
  precise const vec3 e1 = t.v1.xyz - t.v0.xyz, e2 = t.v2.xyz - t.v0.xyz;
  const float ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const vec3 n0 = Cross3(e1 * ke, e2 * ke);
  precise const vec3 n = n0 * InversePowerOfTwo(MaxAbs(n0, n0));
  precise const vec3 w = t.v0.xyz - fc.eye.xyz;
  precise const float tt = Div(Dot3(w, n), Dot3(d, n));
  if (!(tt > 0.0) || !(tt <= 3.40282347e38)) discard;
  // Fault 1: the depth is written without the 1/far scale (so it saturates at 1).
  precise const float depth = kFault == 1u ? tt : tt * fc.params.y;
  gl_FragDepth = min(depth, 1.0);
  out_prim = prim;
  precise const vec3 pos = vec3(fc.eye.x + tt * d.x, fc.eye.y + tt * d.y, fc.eye.z + tt * d.z);
  const Material m = materials[info[prim].ids.x];
  out_diffuse = m.diffuse_reflectivity;
  out_specular = m.specular_shininess;
  out_position = vec4(pos, 1.0);
  out_normal = vec4(ShadingNormal(prim, pos), m.transparency_ior.x);
}
