#version 460
// Raster vertex stage: clip = view_proj * position in the emulator's order (emu raster::VertexStage).
#extension GL_GOOGLE_include_directive : require
#include "rayspace/layout.h"

layout(std430, binding = 0) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 1) readonly buffer Frame { FrameConstants fc; };
// The triangle's index, flat: the fragment stage's gl_PrimitiveID would need the geometryShader
// feature, which many GPUs (tilers) lack.
layout(location = 0) flat out uint v_prim;
layout(constant_id = 0) const uint kFault = 0;  // planted fault (0 = none)

void main() {
  const Triangle t = triangles[gl_VertexIndex / 3];
  const int k = gl_VertexIndex % 3;
  const vec3 p = (k == 0 ? t.v0 : (k == 1 ? t.v1 : t.v2)).xyz;
  precise vec4 c;
  for (int r = 0; r < 4; ++r) {
    precise float a = fc.view_proj[0][r] * p.x;
    precise float b = fc.view_proj[1][r] * p.y;
    precise float d = fc.view_proj[2][r] * p.z;
    c[r] = ((a + b) + d) + fc.view_proj[3][r];
  }
  // Fault 2: every vertex half a pixel to the right, as a device that snaps differently would cover
  // edge pixels differently (docs/gpu.md: edge and interior pixels).
  if (kFault == 2u) c.x += c.w / float(fc.dims.x);
  gl_Position = c;
  v_prim = uint(gl_VertexIndex) / 3u;
}
