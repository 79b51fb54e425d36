#version 460
// Fixed-point accumulator -> 8-bit value with display gamma 2 (sqrt); mirrors emu PassResolve.
// One invocation per channel (an element-wise pass); the byte is written as a uint.
#include "common.glsl"

layout(std430, binding = kResolveBindAccum) readonly buffer Accum { uint64_t accum[]; };
layout(std430, binding = kResolveBindRgb) writeonly buffer Rgb { uint rgb[]; };
layout(push_constant) uniform Block { ElementwisePush pc; };

void main() {
  const uint i = GlobalIndex();
  if (i >= pc.count) return;
  // Fault 3: red and blue swapped (the channel index mirrored within its pixel).
  const uint src = kFault == 3u ? i - i % 3u + (2u - i % 3u) : i;
  precise const float c = Div(float(accum[src]), kAccumScale);
  // Fault 1: the gamma step is skipped.
  const float g = kFault == 1u ? min(max(c, 0.0), 1.0) : Sqrt(min(max(c, 0.0), 1.0));
  // Fault 2: the value is truncated, not rounded (the half is lost).
  precise const float v = kFault == 2u ? g * 255.0 : g * 255.0 + 0.5;
  rgb[i] = uint(v);
}
