#version 460
// 32-bit sort keys per ray; mirrors emu PassHash (emu/src/ray_sort.cpp), or with quad_width > 0
// Roger's quadtree keys (emu PassHashQuadtree).
// Fault 2 (seen only when a launch is folded into rows, --max-groups): GlobalIndex() drops the row.
#define GLOBAL_INDEX_FAULT 2u
#include "common.glsl"

layout(std430, binding = kHashBindRays) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = kHashBindFrame) readonly buffer Frame { FrameConstants fc; };
layout(std430, binding = kHashBindKeys) writeonly buffer Keys { uint keys[]; };
layout(push_constant) uniform Block { HashPush pc; };

uint Cell(float f, int bits) {
  const float cells = float(1u << uint(bits));
  precise const float scaled = f * cells;
  const float v = min(max(scaled, 0.0), cells - 1.0);
  return uint(v);
}

float DiamondAngle(float x, float y) {
  const float ax = abs(x), ay = abs(y);
  precise const float s = ax + ay;
  if (!(s > 0.0)) return 0.0;
  precise float r;
  if (y >= 0.0) r = x >= 0.0 ? Div(y, s) : 1.0 + Div(ax, s);
  else r = x < 0.0 ? 2.0 + Div(ay, s) : 3.0 + Div(x, s);
  return r;
}

uint DirectionKey(vec3 d, int polar_bits, int azimuth_bits, uint order) {
  precise const float pz = (d.z + 1.0) * 0.5;
  precise const float az = DiamondAngle(d.x, d.y) * 0.25;
  const uint p = Cell(pz, polar_bits);
  // Fault 1: the azimuth cell comes from the wrong coordinate pair (x, z).
  const uint a = kFault == 1u ? Cell(DiamondAngle(d.x, d.z) * 0.25, azimuth_bits) : Cell(az, azimuth_bits);
  if (order == kHashOrderPolarFirst) return (p << uint(azimuth_bits)) | a;  // the thesis's layout
  uint key = 0u;
  // Fault 3: the two cells are interleaved azimuth first (swapped operands).
  const uint first = kFault == 3u ? a : p, second = kFault == 3u ? p : a;
  for (int b = max(polar_bits, azimuth_bits) - 1; b >= 0; --b) {
    if (b < polar_bits) key = (key << 1) | ((first >> uint(b)) & 1u);
    if (b < azimuth_bits) key = (key << 1) | ((second >> uint(b)) & 1u);
  }
  return key;
}

uint Interleave3(uint x, uint y, uint z, int bits) {
  uint m = 0u;
  for (int b = bits - 1; b >= 0; --b)
    m = (m << 3) | (((x >> uint(b)) & 1u) << 2) | (((y >> uint(b)) & 1u) << 1) | ((z >> uint(b)) & 1u);
  return m;
}

uint Morton2(uint x, uint y) {
  uint m = 0u;
  for (int b = 15; b >= 0; --b) m = (m << 2) | (((y >> uint(b)) & 1u) << 1) | ((x >> uint(b)) & 1u);
  return m;
}

void main() {
  const uint i = GlobalIndex();
  if (i >= pc.n) return;
  const Ray r = rays[i];
  if (pc.quad_width != 0u) {
    const uint light = r.info.z == kRayShadow ? r.info.w : 0u;
    keys[i] = (light << (2u * pc.quad_depth)) | Morton2(r.info.x % pc.quad_width, r.info.x / pc.quad_width);
    return;
  }
  const vec3 d = Normalize3(r.direction_tmax.xyz);
  if (r.info.z == kRayShadow) {
    const uint light = min(r.info.w, (1u << uint(pc.light_bits)) - 1u);
    keys[i] = (light << uint(pc.polar_bits + pc.azimuth_bits)) | DirectionKey(d, pc.polar_bits, pc.azimuth_bits, pc.order);
  } else {
    precise const vec3 ext = fc.scene_hi.xyz - fc.scene_lo.xyz;
    precise const vec3 rel = r.origin_tmin.xyz - fc.scene_lo.xyz;
    const uint cx = Cell(Div(rel.x, ext.x), pc.origin_bits), cy = Cell(Div(rel.y, ext.y), pc.origin_bits),
               cz = Cell(Div(rel.z, ext.z), pc.origin_bits);
    keys[i] = (Interleave3(cx, cy, cz, pc.origin_bits) << uint(2 * pc.direction_bits)) |
              DirectionKey(d, pc.direction_bits, pc.direction_bits, pc.order);
  }
}
