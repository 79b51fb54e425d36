// The rounded arithmetic of a ray's walk through the regular grid (grid.trace's StepRegular,
// gpu/shaders/grid_trace.comp), templated over the scalar like the other kernel math
// (rayspace/emu/intersect.h): float is the emulator's and the kernel's arithmetic, operation for
// operation; verify::SpecReal asks what a conformant device may compute instead (docs/numerics.md,
// "The relaxed device model"). Each crossing is computed from its boundary, never accumulated, so a
// device's rounding moves each one by a few ULP and no more.
#pragma once
#include <utility>

#include "rayspace/emu/intersect.h"

namespace rayspace::emu::grid {

// The ray's inverse direction and its range [t0, t1] within the box [lo, hi] and [tmin, tmax]
// (`outside`: the ray does not move along an axis and lies outside the box's slab of it). An axis
// with a zero direction component is not divided by: Vulkan bounds no quotient of a zero divisor,
// and IEEE's infinities would give the same range; its inverse is 0, never used.
template <typename S>
struct BoxClipOf {
  Vec3<S> inv;
  S t0, t1;
  bool outside = false;
};
template <typename S>
BoxClipOf<S> BoxClip(Vec3<S> lo, Vec3<S> hi, Vec3<S> org, Vec3<S> dir, S tmin, S tmax) {
  BoxClipOf<S> c{Vec3<S>(S(0.0f)), tmin, tmax};
  for (int a = 0; a < 3; ++a) {
    if (Nominal(dir[a]) == 0.0f) {  // an input word: the same on every device
      c.outside = c.outside || Nominal(org[a]) < Nominal(lo[a]) || Nominal(org[a]) > Nominal(hi[a]);
      continue;
    }
    c.inv[a] = S(1.0f) / dir[a];
    S ta = (lo[a] - org[a]) * c.inv[a], tb = (hi[a] - org[a]) * c.inv[a];
    if (c.inv[a] < S(0.0f)) std::swap(ta, tb);
    c.t0 = Max(c.t0, ta);
    c.t1 = Min(c.t1, tb);
  }
  return c;
}

// Along one axis, the ray's coordinate at t0 in cells from lo (truncated and clamped, its cell).
template <typename S>
S EntryCoordinateOf(S org, S dir, S t0, S lo, S inv_cell) {
  const S p = org + dir * t0;
  return (p - lo) * inv_cell;
}

// Along one axis, the t where the ray crosses boundary k (k cells from lo).
template <typename S>
S CrossingOf(S lo, S cell, int k, S org, S inv) {
  const S boundary = lo + S(static_cast<float>(k)) * cell;
  return (boundary - org) * inv;
}

}  // namespace rayspace::emu::grid
