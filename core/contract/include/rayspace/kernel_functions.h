// Element functions written once for both sides: valid GLSL (the kernels include this file through
// gpu/shaders/common.glsl) and valid C++ (the emulator), so the two cannot drift apart. RS_PRECISE is
// GLSL's `precise` (no contraction, no reassociation); the C++ side gets the same from
// -ffp-contract=off. A function belongs here only when both languages spell the same operations in
// the same order; the others (dot, normalize, ...) are written out on each side in lavapipe's order
// and held together by gpu/tests/drift_test.cpp.
#ifndef RAYSPACE_KERNEL_FUNCTIONS_H
#define RAYSPACE_KERNEL_FUNCTIONS_H

#include "rayspace/layout.h"

#ifdef __cplusplus
namespace rayspace::layout {
using vec3 = glm::vec3;
#define RS_PRECISE
#define RS_INLINE inline
#else
#define RS_PRECISE precise
#define RS_INLINE
#endif

// Direction of the ray through the centre of pixel (px, py): (pixel_origin + px * pixel_dx) +
// py * pixel_dy, each operation rounded to float.
RS_INLINE vec3 PixelDirection(FrameConstants f, uint px, uint py) {
  const float fx = float(px), fy = float(py);
  RS_PRECISE vec3 d;
  for (int k = 0; k < 3; ++k) {
    RS_PRECISE float a = fx * f.pixel_dx[k];
    RS_PRECISE float b = f.pixel_origin[k] + a;
    RS_PRECISE float c = fy * f.pixel_dy[k];
    d[k] = b + c;
  }
  return d;
}

#undef RS_INLINE
#undef RS_PRECISE
#ifdef __cplusplus
}  // namespace rayspace::layout
#endif

#endif  // RAYSPACE_KERNEL_FUNCTIONS_H
