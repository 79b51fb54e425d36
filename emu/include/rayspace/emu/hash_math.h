// The float part of the hash keys (docs/hierarchy.md, "Hash keys"), templated over the scalar like
// intersect.h: float in the emulated pass, verify::SpecReal when the diff bounds what a device may
// compute.
#pragma once
#include "rayspace/emu/intersect.h"

namespace rayspace::emu {

// Pseudo-angle of (x, y) in [0, 4): monotone in the azimuth like atan2, without trigonometry.
template <typename S>
S DiamondAngle(S x, S y) {
  const S ax = Abs(x), ay = Abs(y), s = ax + ay;
  const S zero(0.0f);
  if (!(s > zero)) return zero;
  if (y >= zero) return x >= zero ? y / s : S(1.0f) + ax / s;
  return x < zero ? S(2.0f) + ay / s : S(3.0f) + x / s;
}

// The argument of the polar cell: (cos(theta) + 1) / 2 for the unit direction's z.
template <typename S>
S PolarArgument(S z) { return (z + S(1.0f)) * S(0.5f); }

}  // namespace rayspace::emu
