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
using vec2 = glm::vec2;
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

// ---- the area-light sampler (docs/area-lights.md) ----------------------------------------------
// Integers and correctly rounded sums and products only, so every conformant device draws the same
// points; the shape maps that need a square root are written on each side (emu/light_sample.h,
// gpu/shaders/light_sample.glsl).

// An integer hash: the output permutation of a PCG step (Jarzynski and Olano, "Hash Functions for GPU
// Rendering", JCGT 2020).
RS_INLINE uint SamplerHash(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// The key of one shading point: its pixel and the primitive it lies on, so the bounces of one pixel
// draw different points.
RS_INLINE uint SamplerKey(uint pixel, uint prim) { return SamplerHash(pixel ^ SamplerHash(prim)); }

// Sample k of light `light` at the shading point `key`: stratum (k mod cols, k / cols) of a
// cols x rows grid over the unit square, jittered by two 24-bit hashes. Returns (a, b) in [0, 1]
// (1 only where a product rounds up to it).
RS_INLINE vec2 StratifiedPoint(uint key, uint light, uint k, uint cols, float inv_cols, float inv_rows) {
  const uint h1 = SamplerHash(key ^ SamplerHash((light << 16u) | k));
  const uint h2 = SamplerHash(h1);
  RS_PRECISE float u = float(h1 >> 8u) * 5.9604644775390625e-08f;  // 2^-24: exact
  RS_PRECISE float v = float(h2 >> 8u) * 5.9604644775390625e-08f;
  RS_PRECISE float a = (float(k % cols) + u) * inv_cols;
  RS_PRECISE float b = (float(k / cols) + v) * inv_rows;
  return vec2(a, b);
}

// (cos, sin) of 2 pi b for b in [0, 1]: the quadrant from 4b, then Taylor polynomials of degree 11
// (sine) and 12 (cosine) on [0, pi/2] in Horner form; each component within 2e-7 of the true value.
// Trigonometric built-ins are the driver's own polynomials, which differ between devices.
RS_INLINE vec2 UnitCircle(float b) {
  RS_PRECISE float x = b * 4.0f;
  const uint q = uint(x);
  RS_PRECISE float f = x - float(q);
  RS_PRECISE float t = f * 1.57079637f;
  RS_PRECISE float t2 = t * t;
  RS_PRECISE float ps = -2.50521084e-08f * t2 + 2.75573192e-06f;
  ps = ps * t2 + -1.98412698e-04f;
  ps = ps * t2 + 8.33333333e-03f;
  ps = ps * t2 + -1.66666667e-01f;
  RS_PRECISE float sn = t + (t * t2) * ps;
  RS_PRECISE float pc = 2.08767570e-09f * t2 + -2.75573192e-07f;
  pc = pc * t2 + 2.48015873e-05f;
  pc = pc * t2 + -1.38888889e-03f;
  pc = pc * t2 + 4.16666667e-02f;
  pc = pc * t2 + -0.5f;
  RS_PRECISE float cs = 1.0f + t2 * pc;
  const uint quadrant = q & 3u;
  if (quadrant == 1u) return vec2(-sn, cs);
  if (quadrant == 2u) return vec2(-cs, -sn);
  if (quadrant == 3u) return vec2(sn, -cs);
  return vec2(cs, sn);
}

#undef RS_INLINE
#undef RS_PRECISE
#ifdef __cplusplus
}  // namespace rayspace::layout
#endif

#endif  // RAYSPACE_KERNEL_FUNCTIONS_H
