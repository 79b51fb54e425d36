// The rounded arithmetic of a ray's walk through the regular grid (grid.trace's StepRegular,
// gpu/shaders/grid_trace.comp), templated over the scalar like the other kernel math
// (rayspace/emu/intersect.h): float is the emulator's and the kernel's arithmetic, operation for
// operation; verify::SpecReal asks what a conformant device may compute instead (docs/numerics.md,
// "The relaxed device model"). Each crossing is computed from its boundary, never accumulated, so a
// device's rounding moves each one by a few ULP and no more.
#pragma once
#include <cstdint>
#include <utility>

#include "rayspace/emu/intersect.h"
#include "rayspace/layout.h"

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

// An area light's 3D grid (StepVolume): the ray's parameter range clipped to where g0 + g1 t >= 0.
template <typename S>
void ClipLinearOf(S g0, S g1, S& t0, S& t1) {
  if (g1 > S(0.0f))
    t0 = Max(t0, -g0 / g1);
  else if (g1 < S(0.0f))
    t1 = Min(t1, -g0 / g1);
  else if (g0 < S(0.0f))
    t1 = S(-INFINITY);
}

// The ray's range [t0, t1] within region `region` of a 3D grid about its centre (oq: the origin
// relative to it; zn: the core's half-side): 0..5 a face's frustum beyond the near plane (sides
// widened by kGridFaceSlack), 6 the core.
template <typename S>
void RegionRangeOf(Vec3<S> oq, Vec3<S> dir, S zn, std::uint32_t region, S& t0, S& t1) {
  if (region == layout::kGridFaces) {
    const S h = zn * S(layout::kGridCoreWiden);
    for (int a = 0; a < 3; ++a) {
      ClipLinearOf(h - oq[a], -dir[a], t0, t1);  // oq + dir t <= h
      ClipLinearOf(h + oq[a], dir[a], t0, t1);   // oq + dir t >= -h
    }
    return;
  }
  const std::uint32_t major = region / 2u, ua = (major + 1u) % 3u, vb = (major + 2u) % 3u;
  const S sgn(region % 2u == 0u ? 1.0f : -1.0f);
  const S m0 = sgn * oq[major], dm = sgn * dir[major];
  const S wide = S(1.0f) + S(layout::kGridFaceSlack);
  ClipLinearOf(m0 - zn * S(layout::kGridNearShrink), dm, t0, t1);
  const S wm0 = wide * m0, wdm = wide * dm;
  ClipLinearOf(wm0 - oq[ua], wdm - dir[ua], t0, t1);
  ClipLinearOf(wm0 + oq[ua], wdm + dir[ua], t0, t1);
  ClipLinearOf(wm0 - oq[vb], wdm - dir[vb], t0, t1);
  ClipLinearOf(wm0 + oq[vb], wdm + dir[vb], t0, t1);
}

// A point q (relative to the centre) of face f in perspective space: (u, v) as cell coordinates
// (u + 1) n / 2, and r = 1 / m, m kept at or beyond the near plane. Returns m.
template <typename S>
S PerspectiveOf(Vec3<S> q, std::uint32_t f, S half_n, S near, Vec3<S>& p) {
  const std::uint32_t major = f / 2u, ua = (major + 1u) % 3u, vb = (major + 2u) % 3u;
  const S sgn(f % 2u == 0u ? 1.0f : -1.0f);
  const S m = Max(sgn * q[major], near);
  p = Vec3<S>((q[ua] / m + S(1.0f)) * half_n, (q[vb] / m + S(1.0f)) * half_n, S(1.0f) / m);
  return m;
}

// The fraction of the way from p0 to p0 + delta where a face walk crosses column (row) boundary
// at + 1 (or at, stepping down), and depth boundary `bound`.
template <typename S>
S ColumnCrossingOf(int at, int step, S p0, S d) {
  return (S(static_cast<float>(at + (step > 0 ? 1 : 0))) - p0) / d;
}
template <typename S>
S SliceCrossingOf(S bound, S p0z, S dz) {
  return (bound - p0z) / dz;
}

}  // namespace rayspace::emu::grid
