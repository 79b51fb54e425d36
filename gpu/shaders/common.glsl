// Shared by every kernel: the layouts, the float-control execution mode, and helper functions that
// fix the order of operations to the emulator's (emu/include/rayspace/emu/intersect.h).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_spirv_intrinsics : require
#extension GL_ARB_gpu_shader_int64 : require

// SignedZeroInfNanPreserve (execution mode 4461, capability 4466, 32-bit floats): without it Mesa
// folds a - a to 0, (a + b) - b to a and a*b + a*c to a*(b + c), which the emulator does not.
spirv_execution_mode(extensions = ["SPV_KHR_float_controls"], capabilities = [4466], 4461, 32);

#include "rayspace/layout.h"

layout(constant_id = 0) const uint kFault = 0;  // planted fault (0 = none), selected by `diff --inject`
layout(constant_id = 1) const uint kLocalSize = 64;
layout(local_size_x_id = 1) in;

float Dot3(vec3 a, vec3 b) {
  precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
  return r;
}
float Length3(vec3 v) { return sqrt(Dot3(v, v)); }
