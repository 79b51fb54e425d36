#version 460
// Generation-0 shading points from the G-buffer, one invocation per pixel; mirrors
// emu PassSurfacesFromGBuffer.
#include "common.glsl"

layout(std430, binding = kSurfacesBindPosition) readonly buffer Position { vec4 position[]; };
layout(std430, binding = kSurfacesBindNormal) readonly buffer Normal { vec4 normal[]; };
layout(std430, binding = kSurfacesBindPrim) readonly buffer Prim { uint prim[]; };
layout(std430, binding = kSurfacesBindInfo) readonly buffer Info { TriangleInfo info[]; };
layout(std430, binding = kSurfacesBindFrame) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = kSurfacesBindSurfaces) writeonly buffer Surfaces { Surface surfaces[]; };
layout(push_constant) uniform Block { SurfacesPush pc; };  // this dispatch: pixels base .. base + pixels - 1

void main() {
  const uint i = GlobalIndex();  // element of this dispatch's buffers
  if (i >= pc.pixels) return;
  const uint g = pc.base + i;    // pixel of the frame
  Surface s;
  s.position = vec4(0.0);
  s.normal = vec4(0.0);
  s.incoming = vec4(0.0);
  s.weight = vec4(0.0);
  const uint p = prim[i];
  if (p != kNoPrim) {
    const uint width = fc.dims.x;
    // Fault 1: rows and columns swapped when the pixel index is split.
    const uint px = kFault == 1u ? g / width : g % width, py = kFault == 1u ? g % width : g / width;
    const vec3 d = PixelDirection(fc, px, py);
    // Fault 3: the position is read from the next pixel's texel (an index off by one).
    s.position = vec4(position[kFault == 3u ? i + 1u : i].xyz, 1.0);
    s.normal = vec4(normal[i].xyz, 0.0);
    // Fault 2: the view direction is left unnormalised.
    s.incoming = vec4(kFault == 2u ? d : Normalize3(d), 0.0);
    s.weight = vec4(1.0, 1.0, 1.0, 0.0);
    // Fault 4: the material id read one past the triangle's (an off-by-one index).
    s.info = uvec4(p, g, info[p].ids.x + (kFault == 4u ? 1u : 0u), 0u);
  } else {
    s.info = uvec4(kNoPrim, g, 0u, 0u);
  }
  surfaces[i] = s;
}
