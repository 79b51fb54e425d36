// Shared by every kernel: the layouts, the float-control execution mode, and helper functions that
// fix the order of operations to the emulator's (emu/include/rayspace/emu/intersect.h).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_spirv_intrinsics : require
#extension GL_ARB_gpu_shader_int64 : require

// SignedZeroInfNanPreserve (execution mode 4461, capability 4466, 32-bit floats): without it Mesa
// folds a - a to 0, (a + b) - b to a and a*b + a*c to a*(b + c), which the emulator does not.
spirv_execution_mode(extensions = ["SPV_KHR_float_controls"], capabilities = [4466], 4461, 32);

#include "rayspace/contract.h"
#include "rayspace/kernel_functions.h"  // PixelDirection, shared with the emulator

layout(constant_id = 0) const uint kFault = 0;  // planted fault (0 = none), selected by `diff --inject`
layout(constant_id = 1) const uint kLocalSize = 64;
layout(constant_id = 2) const bool kStrictMath = false;  // --strict-math
layout(local_size_x_id = 1) in;

// This invocation's index in the launch. The host folds launches wider than
// maxComputeWorkGroupCount[0] groups into rows of groups (vk::Recorder::Dispatch); rows are read in
// order, and every kernel skips the indices past its count.
#ifndef GLOBAL_INDEX_FAULT
#define GLOBAL_INDEX_FAULT 0u  // a kernel defines it to plant "the row is ignored" as that fault
#endif
uint GlobalIndex() {
  if (GLOBAL_INDEX_FAULT != 0u && kFault == GLOBAL_INDEX_FAULT) return gl_GlobalInvocationID.x;
  return gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * kLocalSize) + gl_GlobalInvocationID.x;
}

// 2^-e for the exponent e of m > 0, clamped to normal powers (emu InversePowerOfTwo).
float InversePowerOfTwo(float m) {
  const int e = int((floatBitsToUint(m) >> 23) & 0xFFu);
  return uintBitsToFloat(uint(clamp(254 - e, 1, 254)) << 23);
}

// The largest magnitude among the components of a and b (emu MaxAbs).
float MaxAbs(vec3 a, vec3 b) {
  return max(max(max(abs(a.x), abs(a.y)), abs(a.z)), max(max(abs(b.x), abs(b.y)), abs(b.z)));
}

#include "div_sqrt.glsl"  // Div, Sqrt

float Dot3(vec3 a, vec3 b) {
  precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
  return r;
}
float Length3(vec3 v) { return Sqrt(Dot3(v, v)); }
// emu ScaledLength: |v| computed at a power-of-two scale where the squares neither over- nor underflow.
float ScaledLength3(vec3 v) {
  const float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
  if (!(m > 0.0) || !(m < uintBitsToFloat(0x7F800000u))) return m;
  const float k = InversePowerOfTwo(m);
  precise const vec3 s = vec3(v.x * k, v.y * k, v.z * k);
  precise const float l = Div(Sqrt(Dot3(s, s)), k);
  return l;
}
vec3 Normalize3(vec3 v) {
  const float l = Sqrt(Dot3(v, v));
  precise vec3 r = vec3(Div(v.x, l), Div(v.y, l), Div(v.z, l));
  return r;
}
vec3 Cross3(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return r;
}
// x^n by repeated squaring, lowest bit first, never multiplying by a literal 1 (emu IntPow).
float IntPow(float x, uint n) {
  precise float result = 1.0;
  precise float base = x;
  bool first = true;
  while (n != 0u) {
    if ((n & 1u) != 0u) {
      result = first ? base : result * base;
      first = false;
    }
    n >>= 1u;
    if (n != 0u) base = base * base;
  }
  return result;
}
