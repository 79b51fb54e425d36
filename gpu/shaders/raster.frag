#version 460
// Raster fragment stage: depth from the pixel-centre ray and the triangle's plane, written as
// gl_FragDepth, and the primitive id (emu raster::ShadeFragment).
#extension GL_GOOGLE_include_directive : require
#include "rayspace/layout.h"

layout(std430, binding = 0) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 1) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = 2) readonly buffer Normals { TriangleNormals normals[]; };
layout(std430, binding = 3) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = 4) readonly buffer Materials { Material materials[]; };
layout(location = 0) out vec4 out_diffuse;
layout(location = 1) out vec4 out_specular;
layout(location = 2) out vec4 out_position;
layout(location = 3) out vec4 out_normal;
layout(location = 4) out uint out_prim;
layout(constant_id = 0) const uint kFault = 0;  // planted fault (0 = none)

float Dot3(vec3 a, vec3 b) {
  precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
  return r;
}

vec3 Cross3(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return r;
}
vec3 Normalize3(vec3 v) {
  const float l = sqrt(Dot3(v, v));
  precise vec3 r = vec3(v.x / l, v.y / l, v.z / l);
  return r;
}

// Barycentric shading normal from signed sub-areas (emu ShadingNormal).
vec3 ShadingNormal(uint prim, vec3 p) {
  const Triangle t = triangles[prim];
  const TriangleNormals tn = normals[prim];
  const vec3 v0 = t.v0.xyz, v1 = t.v1.xyz, v2 = t.v2.xyz;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  const vec3 n = Cross3(e1, e2);
  precise const vec3 p1 = v1 - p, p2 = v2 - p, p0 = v0 - p;
  const float a0 = Dot3(Cross3(p1, p2), n);
  const float a1 = Dot3(Cross3(p2, p0), n);
  const float a2 = Dot3(Cross3(p0, p1), n);
  precise const float sum = (a0 + a1) + a2;
  precise vec3 s = vec3(0.0);
  if (sum != 0.0) {
    precise const float w0 = a0 / sum, w1 = a1 / sum, w2 = a2 / sum;
    for (int k = 0; k < 3; ++k) s[k] = (tn.n0[k] * w0 + tn.n1[k] * w1) + tn.n2[k] * w2;
  }
  const float len2 = Dot3(s, s);
  if (!(len2 > 0.0) || !(len2 <= 3.0e38)) {
    const float nl = Dot3(n, n);
    if (!(nl > 0.0) || !(nl <= 3.0e38)) return tn.n0.xyz;
    return Normalize3(n);
  }
  return Normalize3(s);
}

void main() {
  const uint prim = uint(gl_PrimitiveID);
  const Triangle t = triangles[prim];
  const uint px = uint(gl_FragCoord.x), py = uint(gl_FragCoord.y);
  precise vec3 d;
  for (int k = 0; k < 3; ++k) {
    precise float a = float(px) * fc.pixel_dx[k];
    precise float b = fc.pixel_origin[k] + a;
    precise float c = float(py) * fc.pixel_dy[k];
    d[k] = b + c;
  }
  precise const vec3 e1 = t.v1.xyz - t.v0.xyz, e2 = t.v2.xyz - t.v0.xyz;
  precise const vec3 n = vec3(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x);
  precise const vec3 w = t.v0.xyz - fc.eye.xyz;
  precise const float tt = Dot3(w, n) / Dot3(d, n);
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
