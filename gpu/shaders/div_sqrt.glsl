// Division and square root are the only float operations of the kernels that Vulkan lets a device
// round loosely (2.5 ULP; sqrt from a 2-ULP inversesqrt). Every shader divides and takes roots through
// these two: under --strict-math (kStrictMath) they are correctly rounded in integer arithmetic
// (rayspace/strict_math.h, shared with tests/strict_math_test.cpp), and the device-like planted
// faults replace them by what many GPUs compute. Needs kFault and kStrictMath declared, and 64-bit
// integers.
#include "rayspace/strict_math.h"

float Div(float a, float b) {
  if (kStrictMath) return DivRN(a, b);
  if (kFault == kFaultApproxDiv) {
    precise const float r = 1.0 / b;
    precise const float q = a * r;
    return q;
  }
  return a / b;
}
float Sqrt(float x) {
  if (kStrictMath) return SqrtRN(x);
  if (kFault == kFaultApproxSqrt) return 1.0 / inversesqrt(x);
  if (kFault == kFaultSqrtHigh && x > 0.0 && x < uintBitsToFloat(0x7F800000u))
    return uintBitsToFloat(floatBitsToUint(sqrt(x)) + 2u);
  return sqrt(x);
}
