// A 64-bit float as any conformant Vulkan device may compute it, the double-precision twin of
// SpecReal (spec_real.h). Vulkan promises double operations only "at least the precision of single
// precision": `v` is the exact IEEE double evaluation (the emulator's and lavapipe's), and [lo, hi]
// holds every value a device carrying 24 significant bits may give for the same operations on the
// same inputs: + - * within 1 ULP of 24 bits of the exact result (either rounding mode), / within 2.5
// (divisors of magnitude in [2^-126, 2^126]), sqrt inherited from 1 / inversesqrt with inversesqrt
// within 2, conversions from float exact, to float in either direction. The grids' build
// (rayspace/emu/grid/bin_math.h) runs on it to judge a device's grid.count (docs/numerics.md).
// Comparisons follow `v` and count in the thread's SpecTrace each decision a permitted value could
// turn the other way, as SpecReal's do.
#pragma once
#include <cstdint>

#include "rayspace/verify/spec_real.h"

namespace rayspace::verify {

struct SpecDouble {
  double v, lo, hi;
  bool any;  // no bound

  SpecDouble() = default;
  SpecDouble(double x);  // NOLINT: constants and widened floats convert implicitly, exactly
  static SpecDouble Unbounded(double nominal);
  bool Allows(double actual) const;
};

SpecDouble operator+(SpecDouble a, SpecDouble b);
SpecDouble operator-(SpecDouble a, SpecDouble b);
SpecDouble operator*(SpecDouble a, SpecDouble b);
SpecDouble operator/(SpecDouble a, SpecDouble b);
SpecDouble operator-(SpecDouble a);
SpecDouble Square(SpecDouble x);
SpecDouble Sqrt(SpecDouble x);
SpecDouble Floor(SpecDouble x);  // exact on every device
// `b < x ? b : x` and `b > x ? b : x` (std::min and std::max of the emulator, MinD and MaxD of the
// kernels): the device's own comparison picks, so no decision is counted.
SpecDouble Lesser(SpecDouble x, SpecDouble b);
SpecDouble Greater(SpecDouble x, SpecDouble b);
// std::clamp(x, lo, hi) with constant bounds (monotone: no decision counted).
SpecDouble ClampOf(SpecDouble x, double lo, double hi);
// A float widened to double: exact on every device.
SpecDouble Widen(SpecReal x);
// The float a conversion gives: round to nearest or toward zero, a denormal possibly flushed.
SpecReal ToFloat(SpecDouble x);

bool operator<(SpecDouble a, SpecDouble b);
bool operator<=(SpecDouble a, SpecDouble b);
bool operator>(SpecDouble a, SpecDouble b);
bool operator>=(SpecDouble a, SpecDouble b);
bool operator==(SpecDouble a, SpecDouble b);
bool operator!=(SpecDouble a, SpecDouble b);

// An integer that rounding leaves between lo and hi: a cell index or a depth slice.
struct IndexRange {
  std::uint32_t lo = 0, hi = 0;
  bool Holds(std::uint32_t x) const { return lo <= x && x <= hi; }
};
// The index a device's (clamped, non-negative) double converts to.
IndexRange CellIndex(SpecDouble x);
// The depth slice of r among `depth` decreasing boundaries b (the emulator's grid::bin::SliceOf):
// between the boundaries r surely lies at or beyond and those it may.
IndexRange SliceOf(SpecDouble r, const float* b, std::uint32_t depth);

}  // namespace rayspace::verify
