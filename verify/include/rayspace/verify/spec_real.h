// A 32-bit float as any conformant Vulkan device may compute it. `v` is the value of the exact IEEE
// evaluation (what lavapipe and the emulator compute, bit for bit); [lo, hi] holds every value the
// SPIR-V precision rules allow for the same operations on the same inputs (docs/numerics.md, "The
// relaxed device model"): add, subtract, multiply, conversions, min/max/abs correctly rounded or
// exact; division within 2.5 ULP for divisors of magnitude in [2^-126, 2^126], anything otherwise;
// sqrt inherited from 1 / inversesqrt with inversesqrt within 2 ULP; without DenormPreserve any
// denormal operand or result may be read or written as zero. The bounds are computed exactly (double
// endpoints, directed rounding to float), so an interval never omits a permitted value.
//
// Kernel math templated over its scalar (emu/include/rayspace/emu/intersect.h) runs on SpecReal to
// classify a device's differing word: inside [lo, hi] the spec allows it; outside it is a bug.
// Comparisons follow `v` (the path lavapipe takes) and count, in the thread's SpecTrace, every
// decision a permitted rounding could have turned the other way: after such a decision the outputs
// are no longer bounded by this evaluation.
#pragma once
#include <cmath>
#include <cstdint>

namespace rayspace::verify {

struct SpecTrace {
  bool flush_denormals = true;  // the device may flush (no DenormPreserve for 32-bit floats)
  std::uint32_t ambiguous = 0;  // decisions the allowed rounding could flip
};

// The innermost active trace on this thread (one is always active; the default flushes).
SpecTrace& CurrentSpecTrace();

class ScopedSpecTrace {
 public:
  explicit ScopedSpecTrace(bool flush_denormals);
  ~ScopedSpecTrace();
  ScopedSpecTrace(const ScopedSpecTrace&) = delete;
  ScopedSpecTrace& operator=(const ScopedSpecTrace&) = delete;
  const SpecTrace& trace() const { return trace_; }

 private:
  SpecTrace trace_;
  SpecTrace* outer_;
};

struct SpecReal {
  // Trivially constructible (glm's vectors keep their components in unions): value-initialise.
  float v, lo, hi;
  bool any;  // no bound: every float (and NaN) is allowed

  SpecReal() = default;
  SpecReal(float x);  // NOLINT: constants and input words convert implicitly, exactly
  static SpecReal Unbounded(float nominal);
  static SpecReal FromInteger(std::uint64_t n);  // float(n) as a device converts it (n < 2^53)
  // Every float in [lo, hi] (a denormal flushed on a flushing device); nominal value v.
  static SpecReal Between(float v, float lo, float hi);
  bool Allows(float actual) const;  // is `actual` a value the rules permit here?
};

SpecReal operator+(SpecReal a, SpecReal b);
SpecReal operator-(SpecReal a, SpecReal b);
SpecReal operator*(SpecReal a, SpecReal b);
SpecReal operator/(SpecReal a, SpecReal b);
SpecReal operator-(SpecReal a);
// x * x: the interval of a value times itself, which no device's rounding makes negative (the
// product of two intervals would admit lo * hi).
SpecReal Square(SpecReal x);
SpecReal Sqrt(SpecReal x);
SpecReal Abs(SpecReal x);
SpecReal Min(SpecReal a, SpecReal b);
SpecReal Max(SpecReal a, SpecReal b);
SpecReal Clamp(SpecReal x, SpecReal lo, SpecReal hi);
// What `b < x ? b : x` (`b > x ? b : x`) gives on a device: the lesser (greater) of its own two
// values, so the interval is [min, min] ([max, max]) of the endpoints, with no decision to count.
SpecReal Lesser(SpecReal x, SpecReal b);
SpecReal Greater(SpecReal x, SpecReal b);
// The next float after x toward `toward`, as a device computes it from the bits (monotone).
SpecReal NextAfter(SpecReal x, float toward);
// 2^-e for the exponent e of |m|, from the nominal value: scaling by it is exact, so any device's
// choice of the power gives the same quotients (see emu InversePowerOfTwo).
SpecReal InversePowerOfTwo(SpecReal m);
inline float Nominal(SpecReal x) { return x.v; }
inline float Nominal(float x) { return x; }

bool operator<(SpecReal a, SpecReal b);
bool operator<=(SpecReal a, SpecReal b);
bool operator>(SpecReal a, SpecReal b);
bool operator>=(SpecReal a, SpecReal b);
bool operator==(SpecReal a, SpecReal b);
bool operator!=(SpecReal a, SpecReal b);

// The spec's ULP of a float value (the gap above |x|'s binade start; 2^-149 for zero and denormals).
double UlpOf(double x);

}  // namespace rayspace::verify
