#version 460
// tl.cells: per (screen cell, list) the window [head, tail) of the packed traversal list that the
// cell's eye rays walk (Toczek et al. section 3.2): every triangle outside it lies wholly outside one
// of the four side planes through the eye of the pyramid spanned by the directions through the
// cell's corner pixels, by more than the margin. One invocation per window, nothing shared between
// invocations. Mirrors emu PassTlCells (emu/src/tl.cpp) and the planes of emu/src/tl_heads.cpp.
#include "common.glsl"

layout(std430, binding = kTlCellsBindFirst) readonly buffer First { uint first[]; };
layout(std430, binding = kTlCellsBindEscapes) readonly buffer Escapes { int escapes[]; };
layout(std430, binding = kTlCellsBindWords) readonly buffer Words { uvec4 words[]; };
layout(std430, binding = kTlCellsBindVertices) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = kTlCellsBindFrame) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = kTlCellsBindWindows) writeonly buffer Windows { uint windows[]; };
layout(push_constant) uniform Block { TlCellsPush pc; };

vec3 eye;
vec3 n[4];
float len[4];

void MakeCellPlanes(uint cell) {
  const uint cx = cell % pc.cells_x, cy = cell / pc.cells_x;
  const uint x0 = cx * kTlCellPixels, y0 = cy * kTlCellPixels;
  const uint x1 = min(x0 + kTlCellPixels, fc.dims.x) - 1u, y1 = min(y0 + kTlCellPixels, fc.dims.y) - 1u;
  vec3 c[4];
  c[0] = PixelDirection(fc, x0, y0);
  c[1] = PixelDirection(fc, x1, y0);
  c[2] = PixelDirection(fc, x1, y1);
  c[3] = PixelDirection(fc, x0, y1);
  precise const vec3 mid = ((c[0] + c[1]) + c[2]) + c[3];
  eye = fc.eye.xyz;
  for (uint j = 0u; j < 4u; ++j) {
    vec3 m = Cross3(c[j], c[(j + 1u) & 3u]);
    if (Dot3(m, mid) < 0.0) m = -m;
    // Fault 1: the first side plane faces the other way.
    if (kFault == 1u && j == 0u) m = -m;
    n[j] = m;
    len[j] = Length3(m);
  }
}

bool SphereRejected(vec4 s) {
  precise const vec3 v = s.xyz - eye;
  for (uint j = 0u; j < 4u; ++j) {
    precise const float h = Dot3(n[j], v) + s.w * len[j], g = -(pc.margin * len[j]);
    if (h < g) return true;
  }
  return false;
}

bool TriangleRejected(vec3 a, vec3 b, vec3 c) {
  precise const vec3 va = a - eye, vb = b - eye, vc = c - eye;
  for (uint j = 0u; j < 4u; ++j) {
    precise const float g = -(pc.margin * len[j]);
    if (Dot3(n[j], va) < g && Dot3(n[j], vb) < g && Dot3(n[j], vc) < g) return true;
  }
  return false;
}

#include "tl_window.glsl"

void main() {
  const uint g = GlobalIndex(), K = pc.lists;
  if (g >= pc.cells * K) return;
  const uint k = g % K;
  // Fault 2: each cell takes the planes of the next cell in x.
  const uint cell = g / K + (kFault == 2u ? 1u : 0u);
  MakeCellPlanes(cell);
  uvec2 w = ListWindow(first[k], first[k + 1u]);
  // Fault 3: a window's tail one element short.
  if (kFault == 3u && w.y > w.x) w.y -= 1u;
  windows[2u * g] = w.x;
  windows[2u * g + 1u] = w.y;
}
